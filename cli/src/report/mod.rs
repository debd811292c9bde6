//! `satflock report RUN_DIR` (and `satflock run --report`): `RUN_DIR/report.html`, one self-contained
//! page that works offline (no network, no other file; its Content-Security-Policy forbids loading
//! anything), built from the run directory alone: the scenario's name, description and TOML, a summary
//! table (`summary.json`), every plot in `RUN_DIR/plots/` (SVG or PNG, embedded) and an animated 3-D view
//! of the swarm in Hill LVLH (the page's own canvas renderer, `viewer.js`; data cut to a budget by
//! [`viewer`]). The same run directory gives the same bytes.

pub mod viewer;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use base64::Engine as _;
use serde::Serialize;
use serde_json::Value;
use thiserror::Error;

use satflock::output::{frames, RunData, RunDataError, Scene};
use satflock::time;

use viewer::ViewerData;

/// The page around the content: placeholders `{{NAME}}`.
const TEMPLATE: &str = include_str!("template.html");
/// The page's style sheet.
const STYLE: &str = include_str!("style.css");
/// The 3-D view (canvas 2-D, no library).
const SCRIPT: &str = include_str!("viewer.js");

/// The report's file name in the run directory.
pub const REPORT_FILE: &str = "report.html";

/// Why a report could not be written.
#[derive(Debug, Error)]
pub enum ReportError {
    /// A file of the run directory cannot be read (the user's input).
    #[error(transparent)]
    Read(#[from] RunDataError),
    /// The report cannot be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// Writes `dir/report.html` (through a temporary file, so a failure leaves no partial page) and returns
/// its path.
pub fn write(dir: &Path) -> Result<PathBuf, ReportError> {
    let html = render(dir)?;
    let path = dir.join(REPORT_FILE);
    let partial = dir.join(format!("{REPORT_FILE}.partial"));
    let written = std::fs::write(&partial, html).and_then(|()| std::fs::rename(&partial, &path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        ReportError::Write {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    })?;
    Ok(path)
}

/// What the page's script reads (JSON in the page).
#[derive(Serialize)]
struct PageData<'a> {
    scene: &'a Scene,
    /// Absent when the run wrote no trajectory.
    trajectory: Option<ViewerData>,
}

/// The page of the run directory `dir`.
pub fn render(dir: &Path) -> Result<String, ReportError> {
    let data = RunData::read(dir)?;
    let trajectory = data.trajectory.as_ref().map(|table| {
        ViewerData::from_trajectory(table, data.n_satellites, |t| {
            time::utc_iso(time::at(data.epoch, t))
        })
    });
    let scenario = ScenarioText::read(dir)?;
    let plots = read_plots(&dir.join("plots"))?;
    let name = data
        .summary
        .get("scenario")
        .and_then(Value::as_str)
        .unwrap_or("(unnamed)");

    let mut body = String::new();
    header(&mut body, name, &scenario, &data);
    summary_section(&mut body, &data, trajectory.as_ref());
    viewer_section(&mut body, trajectory.as_ref(), &data.scene);
    plots_section(&mut body, &plots);

    let page_data = PageData {
        scene: &data.scene,
        trajectory,
    };
    // `<` only occurs inside JSON strings, where `\u003c` is the same character: the script element
    // can then never be closed (or commented) by the data.
    let json = serde_json::to_string(&page_data)
        .expect("the page data serialises")
        .replace('<', "\\u003c");
    Ok(fill(
        TEMPLATE,
        &[
            ("TITLE", &escape(name)),
            ("VERSION", env!("CARGO_PKG_VERSION")),
            ("STYLE", STYLE),
            ("BODY", &body),
            ("DATA", &json),
            ("SCRIPT", SCRIPT),
        ],
    ))
}

/// The template with every `{{NAME}}` replaced, in one pass (inserted text is never scanned again).
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out =
        String::with_capacity(template.len() + values.iter().map(|v| v.1.len()).sum::<usize>());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let end = after
            .find("}}")
            .expect("placeholders are closed in the template");
        let key = &after[..end];
        let value = values
            .iter()
            .find(|(k, _)| *k == key)
            .unwrap_or_else(|| panic!("the template's placeholder {key} has a value"));
        out.push_str(value.1);
        rest = &after[end + 2..];
    }
    out.push_str(rest);
    out
}

/// Text for HTML content and attribute values.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A number for people: integers as such, otherwise six significant digits.
fn number(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    let a = x.abs();
    if x == x.trunc() && a < 1e15 {
        return format!("{x:.0}");
    }
    if (1e-3..1e6).contains(&a) {
        let decimals = (5 - a.log10().floor() as i32).max(0) as usize;
        let text = format!("{x:.decimals$}");
        // Only a fraction's trailing zeros go: 270169.7 is "270170", not "27017".
        return match text.contains('.') {
            true => text.trim_end_matches('0').trim_end_matches('.').to_string(),
            false => text,
        };
    }
    format!("{x:.5e}")
}

/// A JSON value of the summary as HTML: numbers and text inline, small arrays and objects as compact
/// JSON, larger ones folded.
fn value_html(value: &Value) -> String {
    match value {
        Value::Null => "—".into(),
        Value::Bool(b) => if *b { "yes" } else { "no" }.into(),
        Value::Number(n) => n.as_f64().map_or_else(|| n.to_string(), number),
        Value::String(s) => escape(s),
        Value::Array(items)
            if items.len() <= 12 && items.iter().all(|v| v.is_number() || v.is_null()) =>
        {
            let cells: Vec<String> = items.iter().map(value_html).collect();
            format!("[{}]", cells.join(", "))
        }
        Value::Array(_) | Value::Object(_) => {
            let compact = value.to_string();
            if compact.len() <= 80 {
                format!("<code>{}</code>", escape(&compact))
            } else {
                let size = match value {
                    Value::Array(a) => format!("{} items", a.len()),
                    Value::Object(o) => format!("{} keys", o.len()),
                    _ => unreachable!("arrays and objects only"),
                };
                format!(
                    "<details><summary>{size}</summary><pre>{}</pre></details>",
                    escape(&serde_json::to_string_pretty(value).expect("JSON serialises"))
                )
            }
        }
    }
}

/// `scenario.toml` as text, and its description.
struct ScenarioText {
    toml: Option<String>,
    description: Option<String>,
    /// Why the file could not be read as TOML (the page says so; the rest of the report stands).
    problem: Option<String>,
}

impl ScenarioText {
    fn read(dir: &Path) -> Result<Self, RunDataError> {
        let path = dir.join("scenario.toml");
        let toml = match satflock::input_file::read_document(&path) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Ok(Self {
                    toml: None,
                    description: None,
                    problem: None,
                })
            }
            Err(e) => {
                return Err(RunDataError {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })
            }
        };
        let (description, problem) = match toml.parse::<toml::Table>() {
            Ok(table) => (
                table
                    .get("description")
                    .and_then(toml::Value::as_str)
                    .map(str::to_string),
                None,
            ),
            Err(e) => (None, Some(e.to_string())),
        };
        Ok(Self {
            toml: Some(toml),
            description,
            problem,
        })
    }
}

fn header(body: &mut String, name: &str, scenario: &ScenarioText, data: &RunData) {
    let source = data.summary.get("source").and_then(Value::as_str);
    let _ = write!(
        body,
        "<header>\n<h1>{}</h1>\n<p class=\"meta\">satflock run report{}</p>\n",
        escape(name),
        source.map_or(String::new(), |s| format!(
            " · scenario from <code>{}</code>",
            escape(s)
        ))
    );
    if let Some(d) = &scenario.description {
        let _ = writeln!(body, "<p class=\"description\">{}</p>", escape(d));
    }
    match (&scenario.toml, &scenario.problem) {
        (Some(text), problem) => {
            if let Some(p) = problem {
                let _ = writeln!(
                    body,
                    "<p class=\"note\">scenario.toml could not be read as TOML: {}</p>",
                    escape(p)
                );
            }
            let _ = writeln!(
                body,
                "<details id=\"scenario-toml\"><summary>Scenario as run (scenario.toml)</summary>\
                 <pre>{}</pre></details>",
                escape(text)
            );
        }
        (None, _) => {
            body.push_str("<p class=\"note\">This run directory has no scenario.toml.</p>\n")
        }
    }
    body.push_str("</header>\n");
}

fn summary_section(body: &mut String, data: &RunData, trajectory: Option<&ViewerData>) {
    let s = &data.summary;
    let get = |path: &str| -> &Value {
        path.split('.')
            .try_fold(s, |v, key| v.get(key))
            .unwrap_or(&Value::Null)
    };
    let mut rows: Vec<(String, String)> = Vec::new();
    let mut row = |label: &str, html: String| rows.push((label.to_string(), html));

    let mut status = value_html(get("status"));
    if let Some(e) = get("error").as_str() {
        let _ = write!(status, ": {}", escape(e));
    }
    row("Status", status);
    let warnings = get("warnings").as_array().cloned().unwrap_or_default();
    row(
        "Warnings",
        if warnings.is_empty() {
            "none".into()
        } else {
            let items: String = warnings
                .iter()
                .map(|w| format!("<li>{}</li>", value_html(w)))
                .collect();
            format!("<ul>{items}</ul>")
        },
    );
    row("Satellites", value_html(get("n_satellites")));
    let mut duration = value_html(get("duration_s"));
    if get("simulated_s") != get("duration_s") {
        let _ = write!(duration, " (simulated {})", value_html(get("simulated_s")));
    }
    row("Duration [s]", duration);
    row(
        "Epoch (UTC)",
        format!(
            "{} (time system {})",
            escape(&time::utc_iso(data.epoch)),
            value_html(get("time_system"))
        ),
    );
    row("Seed", value_html(get("seed")));
    let frames_text = match trajectory {
        Some(t) => format!(
            "{} in metrics.csv; trajectory.csv: {} times × {} satellites",
            data.metrics.rows(),
            t.n_times_recorded,
            t.n_satellites_recorded
        ),
        None => format!("{} in metrics.csv; no trajectory.csv", data.metrics.rows()),
    };
    row("Recorded times", frames_text);
    row(
        "Delta-v mean / max [m/s]",
        format!(
            "{} / {}",
            value_html(get("delta_v_mps.mean")),
            value_html(get("delta_v_mps.max"))
        ),
    );
    row(
        "Minimum separation [m]",
        value_html(get("min_separation_m")),
    );
    row(
        "Collisions (most pairs at once)",
        value_html(get("collisions")),
    );
    if let Some(fe) = get("final.five_elements").as_object() {
        for (key, label) in [
            ("d_max_m", "Final d_max [m]"),
            ("diameter_m", "Final diameter [m]"),
            ("d_min_m", "Final d_min [m]"),
            ("uniformity_l", "Final uniformity L"),
        ] {
            if let Some(v) = fe.get(key) {
                row(label, value_html(v));
            }
        }
    }
    row(
        "Run",
        format!(
            "{} s wall time, {} satellite-steps/s, {} threads, satflock {}",
            value_html(get("wall_time_s")),
            value_html(get("satellite_steps_per_s")),
            value_html(get("threads")),
            value_html(get("metadata.satflock_version"))
        ),
    );
    row("Hill LVLH", escape(frames::LVLH_FRAME_DESCRIPTION));
    row("Inertial frame", escape(frames::INERTIAL_FRAME_DESCRIPTION));

    body.push_str("<section id=\"summary\">\n<h2>Summary</h2>\n<table class=\"summary\">\n");
    for (label, html) in &rows {
        let _ = writeln!(body, "<tr><th>{}</th><td>{html}</td></tr>", escape(label));
    }
    for (title, id, value) in [
        (
            "Environment (threats and obstacles)",
            "environment",
            get("environment"),
        ),
        ("The law's results (summary.json law)", "law", get("law")),
    ] {
        let Some(object) = value.as_object().filter(|o| !o.is_empty()) else {
            continue;
        };
        let _ = writeln!(
            body,
            "<tr class=\"group\" id=\"summary-{id}\"><th colspan=\"2\">{title}</th></tr>"
        );
        for (key, v) in object {
            let html = closest_html(v, key, get("environment")).unwrap_or_else(|| value_html(v));
            let _ = writeln!(
                body,
                "<tr><th><code>{}</code></th><td>{html}</td></tr>",
                escape(key)
            );
        }
    }
    body.push_str("</table>\n</section>\n");
}

/// The environment's `closest_threat_approach` and `min_obstacle_clearance` in words: satellite,
/// object by name, time and distance.
fn closest_html(value: &Value, key: &str, environment: &Value) -> Option<String> {
    let (names, field, what) = match key {
        "closest_threat_approach" => ("threats", "distance_m", "distance"),
        "min_obstacle_clearance" => ("obstacles", "clearance_m", "clearance"),
        _ => return None,
    };
    let satellite = value.get("satellite")?.as_u64()?;
    let object = value.get("object")?.as_u64()?;
    let minimum = value.get("minimum")?;
    let name = environment
        .get(names)
        .and_then(|n| n.get(object as usize))
        .and_then(Value::as_str)
        .map_or_else(|| format!("#{object}"), str::to_string);
    Some(format!(
        "satellite {satellite} and {}: {what} {} m at t = {} s",
        escape(&name),
        value_html(minimum.get(field)?),
        value_html(minimum.get("time_s")?)
    ))
}

fn viewer_section(body: &mut String, trajectory: Option<&ViewerData>, scene: &Scene) {
    body.push_str("<section id=\"viewer\">\n<h2>The swarm in Hill LVLH</h2>\n");
    let Some(t) = trajectory else {
        body.push_str(
            "<p class=\"note\" id=\"viewer-none\">This run wrote no trajectory.csv, so there is \
             nothing to animate (set <code>[output] trajectory = true</code> in the scenario).</p>\n\
             </section>\n",
        );
        return;
    };
    let _ = writeln!(
        body,
        "<p id=\"viewer-kept\" data-satellites=\"{}\" data-times=\"{}\">{}</p>",
        t.satellite_ids.len(),
        t.times_s.len(),
        escape(&t.kept_sentence())
    );
    let mut objects = Vec::new();
    if !scene.threats.is_empty() {
        objects.push(format!(
            "{} threat(s) as moving points with their danger spheres",
            scene.threats.len()
        ));
    }
    if !scene.obstacles.is_empty() {
        objects.push(format!("{} obstacle(s) as spheres", scene.obstacles.len()));
    }
    if scene.target_formation_lvlh_m.is_some() {
        objects.push("the target formation as crosses".into());
    }
    let _ = writeln!(
        body,
        "<p class=\"hint\">Orthographic view, x radial outward, y along-track, z orbit normal; drag to \
         rotate, wheel to zoom.{}</p>",
        if objects.is_empty() {
            String::new()
        } else {
            format!(" Also drawn: {}.", objects.join(", "))
        }
    );
    body.push_str(
        "<div class=\"controls\">\n\
         <button type=\"button\" id=\"play\">Play</button>\n\
         <input type=\"range\" id=\"time-slider\" min=\"0\" value=\"0\" step=\"1\" aria-label=\"time\">\n\
         <span id=\"time-display\"></span>\n\
         </div>\n\
         <div class=\"controls\">\n\
         <label>speed <select id=\"speed\"><option value=\"0.25\">¼×</option><option value=\"1\" selected>1×</option>\
         <option value=\"4\">4×</option></select></label>\n\
         <label>colour by <select id=\"colour-by\"><option value=\"\">one colour</option></select></label>\n\
         <button type=\"button\" id=\"reset-view\">reset view</button>\n\
         </div>\n\
         <div class=\"stage\"><canvas id=\"view\"></canvas><div id=\"legend\"></div></div>\n",
    );
    body.push_str("</section>\n");
}

/// A plot file of `RUN_DIR/plots/`.
struct Plot {
    name: String,
    mime: &'static str,
    bytes: Vec<u8>,
}

fn read_plots(dir: &Path) -> Result<Vec<Plot>, RunDataError> {
    let error = |path: &Path, e: std::io::Error| RunDataError {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(error(dir, e)),
    };
    let mut plots = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| error(dir, e))?;
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        let mime = match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("svg") => "image/svg+xml",
            Some(e) if e.eq_ignore_ascii_case("png") => "image/png",
            _ => continue,
        };
        if !path.is_file() {
            continue;
        }
        let bytes = satflock::input_file::read(&path, satflock::input_file::MAX_TABLE_BYTES)
            .map_err(|e| error(&path, e))?;
        plots.push(Plot { name, mime, bytes });
    }
    // Each figure once: `satflock plot` writes every figure as SVG and PNG; the SVG (vector, crisp
    // text) is kept, a PNG only where no SVG of the same name exists.
    let stem = |name: &str| name.rsplit_once('.').map_or(name, |(s, _)| s).to_string();
    let svg_stems: Vec<String> = plots
        .iter()
        .filter(|p| p.mime == "image/svg+xml")
        .map(|p| stem(&p.name))
        .collect();
    plots.retain(|p| p.mime == "image/svg+xml" || !svg_stems.contains(&stem(&p.name)));
    plots.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(plots)
}

/// Smallest text a report figure may show \[CSS px\].
const MIN_FIGURE_TEXT_PX: u32 = 11;

/// The narrowest a figure `width` px wide may be shown so that its smallest text (the tick labels,
/// [`crate::plot::size::TICKS`]) is at least [`MIN_FIGURE_TEXT_PX`].
fn min_display_width(width: u32) -> u32 {
    (width * MIN_FIGURE_TEXT_PX).div_ceil(crate::plot::size::TICKS)
}

/// A figure's width in pixels: an SVG's `width` attribute, a PNG's header; `None` if it has none.
fn figure_width(plot: &Plot) -> Option<u32> {
    if plot.mime == "image/png" {
        let bytes: [u8; 4] = plot.bytes.get(16..20)?.try_into().ok()?;
        return Some(u32::from_be_bytes(bytes));
    }
    let head = String::from_utf8_lossy(plot.bytes.get(..plot.bytes.len().min(1024))?);
    let start = head.find("<svg")?;
    let rest = &head[start..];
    let value = &rest[rest.find(" width=\"")? + 8..];
    value[..value.find('"')?]
        .trim_end_matches("px")
        .parse()
        .ok()
}

fn plots_section(body: &mut String, plots: &[Plot]) {
    body.push_str("<section id=\"plots\">\n<h2>Plots</h2>\n");
    if plots.is_empty() {
        body.push_str(
            "<p class=\"note\" id=\"plots-none\">No plots (run <code>satflock plot DIR</code>, then \
             <code>satflock report DIR</code> again).</p>\n",
        );
    }
    for plot in plots {
        // As images (data URLs): an image's own links are never fetched and its scripts never run.
        // Shrunk to the page at most down to a scale that keeps the smallest text readable; a wider
        // figure scrolls in its frame.
        let min_width = figure_width(plot)
            .map(|w| format!(" style=\"min-width: {}px\"", min_display_width(w)))
            .unwrap_or_default();
        let _ = writeln!(
            body,
            "<figure><img alt=\"{name}\"{min_width} src=\"data:{};base64,{}\"><figcaption>{name}</figcaption></figure>",
            plot.mime,
            base64::engine::general_purpose::STANDARD.encode(&plot.bytes),
            name = escape(&plot.name)
        );
    }
    body.push_str("</section>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_keep_their_text_at_least_11_px() {
        let svg = Plot {
            name: "tracks.svg".into(),
            mime: "image/svg+xml",
            bytes: b"<svg width=\"1800\" height=\"680\" viewBox=\"0 0 1800 680\" xmlns=\"x\">"
                .to_vec(),
        };
        assert_eq!(figure_width(&svg), Some(1800));
        let mut png = vec![0u8; 24];
        png[16..20].copy_from_slice(&1400u32.to_be_bytes());
        let png = Plot {
            name: "delta_v.png".into(),
            mime: "image/png",
            bytes: png,
        };
        assert_eq!(figure_width(&png), Some(1400));
        for width in [1000, 1400, 1800] {
            let shown = min_display_width(width);
            let text_px = f64::from(crate::plot::size::TICKS) * f64::from(shown) / f64::from(width);
            assert!(text_px >= 11.0, "{width}: {text_px}");
        }
        let mut body = String::new();
        plots_section(&mut body, &[svg]);
        assert!(body.contains("style=\"min-width: 1524px\""), "{body}");
    }

    #[test]
    fn numbers_and_text_for_people() {
        assert_eq!(number(3.0), "3");
        assert_eq!(number(-0.5), "-0.5");
        assert_eq!(number(5.9570903740594), "5.95709");
        assert_eq!(number(170644.6512313958), "170645");
        assert_eq!(number(1.25e-5), "1.25000e-5");
        // A table of values across the decades, integers' own zeros kept (issue 25: 270169.7 was
        // "27017", 100000.4 was "1").
        for (x, text) in [
            (270169.7, "270170"),
            (100000.4, "100000"),
            (999999.4, "999999"),
            (120000.25, "120000"),
            (10000.5, "10000.5"),
            (1000.04, "1000.04"),
            (0.00100, "0.001"),
            (0.0012345678, "0.00123457"),
            (-250000.2, "-250000"),
            (1.0e6 + 0.5, "1.00000e6"),
            (100.0, "100"),
        ] {
            assert_eq!(number(x), text, "{x}");
        }
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
        // Placeholders are filled once: inserted text is not scanned.
        assert_eq!(
            fill("<{{A}}|{{B}}>", &[("A", "{{B}}"), ("B", "b")]),
            "<{{B}}|b>"
        );
    }
}
