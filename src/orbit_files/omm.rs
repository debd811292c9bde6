//! CCSDS Orbit Mean-elements Messages (OMM, CCSDS 502.0-B-2/-3) of SGP4 element sets, in the three
//! encodings the catalogue publishes (CelesTrak's and Space-Track's "GP" data): KVN, XML and JSON,
//! told apart by the first character (`{` or `[` JSON, `<` XML, else KVN), read into
//! [`Sgp4Object`]s in file order ([`read_omm_file`], [`parse_omm`]).
//!
//! * **KVN**: one or more messages, each starting `CCSDS_OMM_VERS = 2.0` (or `3.0`), then
//!   `KEYWORD = value` lines (`COMMENT`s and blank lines skipped, a trailing `[unit]` dropped).
//! * **XML**: the CCSDS NDM/XML schema, `<omm>` elements (inside an `<ndm>` or alone), each leaf
//!   element (`<EPOCH>…</EPOCH>`, …) a keyword; attributes, comments and `<COMMENT>`s skipped.
//! * **JSON**: an object or an array of objects whose members are the keywords (CelesTrak's
//!   `FORMAT=json`); numbers as numbers or strings.
//!
//! Every encoding gives the same keywords, checked the same way into [`sgp4::Elements`]:
//!
//! * mandatory (a missing one is an error naming it): `EPOCH`, `MEAN_MOTION` \[rev/day\],
//!   `ECCENTRICITY`, `INCLINATION`, `RA_OF_ASC_NODE`, `ARG_OF_PERICENTER`, `MEAN_ANOMALY` \[deg\],
//!   `BSTAR` \[1/earth radii\], `MEAN_MOTION_DOT` \[rev/day²\], `MEAN_MOTION_DDOT` \[rev/day³\]; and in
//!   KVN and XML, which carry the standard's metadata, `OBJECT_NAME`, `OBJECT_ID`, `CENTER_NAME`,
//!   `REF_FRAME`, `TIME_SYSTEM`, `MEAN_ELEMENT_THEORY`;
//! * checked when present: `CENTER_NAME = EARTH`, `REF_FRAME = TEME`, `TIME_SYSTEM = UTC`,
//!   `MEAN_ELEMENT_THEORY = SGP4` (or `SGP/SGP4`), `EPHEMERIS_TYPE` 0, 2 or 3 (4 is SGP4-XP, which
//!   SGP4 cannot propagate);
//! * bookkeeping, which SGP4 does not use, read when present: `NORAD_CAT_ID` (else 0),
//!   `CLASSIFICATION_TYPE` (else `U`), `ELEMENT_SET_NO` (else 0), `REV_AT_EPOCH` (else 0);
//! * any other keyword (header, spacecraft parameters, covariance, user-defined) is skipped; a
//!   keyword given twice in one element set is an error.

use std::collections::BTreeMap;
use std::path::Path;

use super::epoch::{parse_ccsds_epoch, TimeSystem, EPOCH_FORMATS};
use super::error::OrbitFileError;
use super::kvn::{self, Kvn};
use super::sgp4_object::Sgp4Object;

/// One keyword's value and line.
#[derive(Clone, Debug)]
struct Field {
    value: String,
    line: Option<usize>,
}

/// One element set's keywords, before checking.
#[derive(Debug, Default)]
struct RawSet {
    /// Where it starts (KVN, XML), or none (JSON).
    line: Option<usize>,
    /// Whether the encoding carries the standard's metadata (KVN, XML), which is then mandatory.
    standard: bool,
    fields: BTreeMap<String, Field>,
    /// A keyword given twice, kept to report.
    duplicate: Option<(String, Option<usize>)>,
}

impl RawSet {
    fn insert(&mut self, key: &str, value: String, line: Option<usize>) {
        if !is_used(key) {
            return;
        }
        if self.fields.contains_key(key) && self.duplicate.is_none() {
            self.duplicate = Some((key.to_string(), line));
        }
        self.fields.insert(key.to_string(), Field { value, line });
    }
}

/// The standard's metadata, mandatory in KVN and XML.
const METADATA: [&str; 6] = [
    "OBJECT_NAME",
    "OBJECT_ID",
    "CENTER_NAME",
    "REF_FRAME",
    "TIME_SYSTEM",
    "MEAN_ELEMENT_THEORY",
];

/// The mean elements and drag terms SGP4 needs, mandatory in every encoding.
const ELEMENTS: [&str; 10] = [
    "EPOCH",
    "MEAN_MOTION",
    "ECCENTRICITY",
    "INCLINATION",
    "RA_OF_ASC_NODE",
    "ARG_OF_PERICENTER",
    "MEAN_ANOMALY",
    "BSTAR",
    "MEAN_MOTION_DOT",
    "MEAN_MOTION_DDOT",
];

/// Bookkeeping keywords, read when present.
const BOOKKEEPING: [&str; 5] = [
    "EPHEMERIS_TYPE",
    "CLASSIFICATION_TYPE",
    "NORAD_CAT_ID",
    "ELEMENT_SET_NO",
    "REV_AT_EPOCH",
];

/// Whether `key` is read (the others are skipped).
fn is_used(key: &str) -> bool {
    METADATA.contains(&key) || ELEMENTS.contains(&key) || BOOKKEEPING.contains(&key)
}

/// OMM versions read.
const VERSIONS: &str = "2.0 or 3.0";

/// The element sets of an OMM file (KVN, XML or JSON), in file order.
pub fn read_omm_file(path: &Path) -> Result<Vec<Sgp4Object>, OrbitFileError> {
    let text = super::read_text(path)?;
    parse_omm(&text, &path.display().to_string())
}

/// The element sets of OMM text (KVN, XML or JSON); `file` names it in errors.
pub fn parse_omm(text: &str, file: &str) -> Result<Vec<Sgp4Object>, OrbitFileError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let raw = match text.trim_start().chars().next() {
        Some('{' | '[') => json_sets(text, file)?,
        Some('<') => xml_sets(text, file)?,
        _ => kvn_sets(text, file)?,
    };
    if raw.is_empty() {
        return Err(OrbitFileError::no_element_set(
            file,
            "one or more OMM element sets (KVN, XML or JSON)",
        ));
    }
    raw.into_iter()
        .enumerate()
        .map(|(i, set)| element_set(file, i + 1, set))
        .collect()
}

fn kvn_sets(text: &str, file: &str) -> Result<Vec<RawSet>, OrbitFileError> {
    let mut sets: Vec<RawSet> = Vec::new();
    for (line, kind) in kvn::lines(text) {
        match kind {
            Kvn::Blank | Kvn::Comment => {}
            Kvn::Pair("CCSDS_OMM_VERS", version) => {
                check_version(file, Some(line), version)?;
                sets.push(RawSet {
                    line: Some(line),
                    standard: true,
                    ..RawSet::default()
                });
            }
            Kvn::Pair(key, value) => {
                match sets.last_mut() {
                    Some(set) => set.insert(key, value.to_string(), Some(line)),
                    None => return Err(OrbitFileError::invalid(
                        file,
                        Some(line),
                        key,
                        value,
                        "before the first CCSDS_OMM_VERS",
                        "an OMM in KVN starting `CCSDS_OMM_VERS = 2.0`, an XML OMM or a JSON OMM",
                    )),
                }
            }
            Kvn::Other(other) => {
                return Err(OrbitFileError::invalid(
                    file,
                    Some(line),
                    "line",
                    other,
                    "not a `KEYWORD = value` line",
                    "KVN lines `KEYWORD = value`, COMMENT lines and blank lines",
                ))
            }
        }
    }
    Ok(sets)
}

fn check_version(file: &str, line: Option<usize>, version: &str) -> Result<(), OrbitFileError> {
    match version.trim() {
        "2.0" | "3.0" => Ok(()),
        v => Err(OrbitFileError::invalid(
            file,
            line,
            "CCSDS_OMM_VERS",
            v,
            "an OMM version satflock does not read",
            VERSIONS,
        )),
    }
}

fn json_sets(text: &str, file: &str) -> Result<Vec<RawSet>, OrbitFileError> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        OrbitFileError::invalid(
            file,
            Some(e.line()),
            "JSON",
            "",
            e.to_string(),
            "a JSON object or array of objects of OMM keywords (CelesTrak's FORMAT=json)",
        )
    })?;
    let objects = match value {
        serde_json::Value::Array(items) => items,
        object @ serde_json::Value::Object(_) => vec![object],
        _ => Vec::new(),
    };
    objects
        .into_iter()
        .enumerate()
        .map(|(i, item)| {
            let serde_json::Value::Object(members) = item else {
                return Err(OrbitFileError::invalid(
                    file,
                    None,
                    &format!("element set {}", i + 1),
                    &item.to_string(),
                    "not a JSON object",
                    "a JSON object of OMM keywords",
                ));
            };
            let mut set = RawSet::default();
            for (key, value) in members {
                let text = match value {
                    serde_json::Value::Null => continue,
                    serde_json::Value::String(s) => s,
                    other => other.to_string(),
                };
                set.insert(&key, text, None);
            }
            Ok(set)
        })
        .collect()
}

/// `&lt;` `&gt;` `&amp;` `&quot;` `&apos;` and numeric character references.
fn xml_unescape(text: &str) -> Option<String> {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        let semi = rest[amp..].find(';')? + amp;
        let entity = &rest[amp + 1..semi];
        let c = match entity {
            "lt" => '<',
            "gt" => '>',
            "amp" => '&',
            "quot" => '"',
            "apos" => '\'',
            _ => {
                let code = match entity.strip_prefix("#x") {
                    Some(hex) => u32::from_str_radix(hex, 16).ok()?,
                    None => entity.strip_prefix('#')?.parse().ok()?,
                };
                char::from_u32(code)?
            }
        };
        out.push(c);
        rest = &rest[semi + 1..];
    }
    out.push_str(rest);
    Some(out)
}

/// The element sets of an XML OMM: each `<omm>` element's leaf elements.
fn xml_sets(text: &str, file: &str) -> Result<Vec<RawSet>, OrbitFileError> {
    let allowed = "well-formed XML of the CCSDS NDM/XML schema (<omm> elements)";
    let line_of = |pos: usize| text[..pos].matches('\n').count() + 1;
    let bad = |pos: usize, what: &str, problem: &str| {
        OrbitFileError::invalid(file, Some(line_of(pos)), "XML", what, problem, allowed)
    };
    // Open elements: name, start, whether it has child elements.
    let mut stack: Vec<(String, usize, bool)> = Vec::new();
    let mut sets: Vec<RawSet> = Vec::new();
    let mut in_omm = false;
    let mut content = String::new();
    let mut pos = 0;
    while let Some(offset) = text[pos..].find('<') {
        content.push_str(&text[pos..pos + offset]);
        let start = pos + offset;
        let rest = &text[start..];
        let skip_to = |end: &str| rest.find(end).map(|e| start + e + end.len());
        if rest.starts_with("<?") {
            pos =
                skip_to("?>").ok_or_else(|| bad(start, "<?", "unclosed processing instruction"))?;
            continue;
        }
        if rest.starts_with("<!--") {
            pos = skip_to("-->").ok_or_else(|| bad(start, "<!--", "unclosed comment"))?;
            continue;
        }
        if let Some(cdata) = rest.strip_prefix("<![CDATA[") {
            let end = cdata
                .find("]]>")
                .ok_or_else(|| bad(start, "<![CDATA[", "unclosed CDATA"))?;
            content.push_str(&cdata[..end]);
            pos = start + 9 + end + 3;
            continue;
        }
        if rest.starts_with("<!") {
            pos = skip_to(">").ok_or_else(|| bad(start, "<!", "unclosed declaration"))?;
            continue;
        }
        let end = rest
            .find('>')
            .ok_or_else(|| bad(start, "<", "unclosed tag"))?
            + start;
        let tag = &text[start + 1..end];
        pos = end + 1;
        if let Some(name) = tag.strip_prefix('/') {
            let name = name.trim();
            let Some((open, open_at, has_children)) = stack.pop() else {
                return Err(bad(start, tag, "a closing tag with no element open"));
            };
            if open != name {
                return Err(bad(
                    start,
                    tag,
                    &format!("closes <{open}> opened on line {}", line_of(open_at)),
                ));
            }
            if name == "omm" {
                in_omm = false;
            } else if in_omm && !has_children {
                let value = xml_unescape(content.trim())
                    .ok_or_else(|| bad(open_at, &content, "a malformed character reference"))?;
                if let Some(set) = sets.last_mut() {
                    set.insert(name, value, Some(line_of(open_at)));
                }
            }
            content.clear();
            continue;
        }
        let self_closing = tag.ends_with('/');
        let body = tag.trim_end_matches('/');
        let name = body.split_whitespace().next().unwrap_or("").to_string();
        if name.is_empty() {
            return Err(bad(start, tag, "a tag without a name"));
        }
        if let Some(parent) = stack.last_mut() {
            parent.2 = true;
        }
        content.clear();
        if name == "omm" {
            if let Some(version) = attribute(body, "version") {
                check_version(file, Some(line_of(start)), version)?;
            }
            in_omm = true;
            sets.push(RawSet {
                line: Some(line_of(start)),
                standard: true,
                ..RawSet::default()
            });
        }
        if !self_closing {
            stack.push((name, start, false));
        }
    }
    if let Some((open, open_at, _)) = stack.last() {
        return Err(bad(*open_at, open, "an element that is never closed"));
    }
    Ok(sets)
}

/// The value of attribute `name` in a start tag's text.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let at = tag.find(&format!("{name}="))? + name.len() + 1;
    let quote = tag[at..].chars().next()?;
    let rest = &tag[at + 1..];
    rest.find(quote).map(|end| &rest[..end])
}

/// Checks one element set's keywords and builds its propagator.
fn element_set(file: &str, index: usize, set: RawSet) -> Result<Sgp4Object, OrbitFileError> {
    let block = match set.fields.get("OBJECT_NAME") {
        Some(name) => format!("OMM element set {index} ({})", name.value),
        None => format!("OMM element set {index}"),
    };
    if let Some((key, line)) = &set.duplicate {
        return Err(OrbitFileError::invalid(
            file,
            *line,
            key,
            &set.fields[key].value,
            format!("given twice in {block}"),
            "each keyword once per element set",
        ));
    }
    let mandatory = ELEMENTS
        .iter()
        .chain(if set.standard { &METADATA[..] } else { &[] });
    for key in mandatory {
        if !set.fields.contains_key(*key) {
            return Err(OrbitFileError::missing(file, set.line, &block, key, None));
        }
    }
    let get = |key: &str| set.fields.get(key);
    let invalid = |key: &str, f: &Field, problem: &str, allowed: &str| {
        OrbitFileError::invalid(
            file,
            f.line,
            key,
            &f.value,
            problem.to_string(),
            allowed.to_string(),
        )
    };
    for (key, allowed) in [
        ("CENTER_NAME", &["EARTH"][..]),
        ("REF_FRAME", &["TEME"][..]),
        ("TIME_SYSTEM", &["UTC"][..]),
        ("MEAN_ELEMENT_THEORY", &["SGP4", "SGP/SGP4"][..]),
    ] {
        if let Some(f) = get(key) {
            if !allowed
                .iter()
                .any(|a| a.eq_ignore_ascii_case(f.value.trim()))
            {
                return Err(invalid(
                    key,
                    f,
                    "not what SGP4 element sets are given in",
                    &allowed.join(" or "),
                ));
            }
        }
    }
    let float = |key: &str| -> Result<f64, OrbitFileError> {
        let f = &set.fields[key];
        f.value
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| invalid(key, f, "not a number", "a finite decimal number"))
    };
    let integer = |key: &str| -> Result<u64, OrbitFileError> {
        match get(key) {
            None => Ok(0),
            Some(f) => f
                .value
                .trim()
                .parse::<u64>()
                .map_err(|_| invalid(key, f, "not a whole number", "a whole number >= 0")),
        }
    };
    let epoch_field = &set.fields["EPOCH"];
    let epoch = parse_ccsds_epoch(&epoch_field.value, TimeSystem::Utc)
        .map_err(|e| invalid("EPOCH", epoch_field, &e, EPOCH_FORMATS))?;
    let (y, mo, d, h, mi, s, ns) = epoch.to_gregorian_utc();
    let datetime = sgp4::chrono::NaiveDate::from_ymd_opt(y, u32::from(mo), u32::from(d))
        .and_then(|date| {
            date.and_hms_nano_opt(
                u32::from(h),
                u32::from(mi),
                u32::from(s.min(59)),
                ns + if s == 60 { 1_000_000_000 } else { 0 },
            )
        })
        .ok_or_else(|| invalid("EPOCH", epoch_field, "not a valid date", EPOCH_FORMATS))?;
    let ephemeris_type = integer("EPHEMERIS_TYPE")?;
    if !matches!(ephemeris_type, 0 | 2 | 3) {
        return Err(invalid(
            "EPHEMERIS_TYPE",
            &set.fields["EPHEMERIS_TYPE"],
            "not an SGP4 element set (4 is SGP4-XP)",
            "0, 2 or 3 (SGP4/SDP4)",
        ));
    }
    let classification = match get("CLASSIFICATION_TYPE").map(|f| (f, f.value.trim())) {
        None | Some((_, "U")) => sgp4::Classification::Unclassified,
        Some((_, "C")) => sgp4::Classification::Classified,
        Some((_, "S")) => sgp4::Classification::Secret,
        Some((f, _)) => return Err(invalid("CLASSIFICATION_TYPE", f, "unknown", "U, C or S")),
    };
    let eccentricity = float("ECCENTRICITY")?;
    if !(0.0..1.0).contains(&eccentricity) {
        return Err(invalid(
            "ECCENTRICITY",
            &set.fields["ECCENTRICITY"],
            "not an ellipse",
            "0 <= ECCENTRICITY < 1",
        ));
    }
    let mean_motion = float("MEAN_MOTION")?;
    if mean_motion <= 0.0 {
        return Err(invalid(
            "MEAN_MOTION",
            &set.fields["MEAN_MOTION"],
            "not positive",
            "a mean motion > 0 rev/day",
        ));
    }
    let elements = sgp4::Elements {
        object_name: get("OBJECT_NAME").map(|f| f.value.trim().to_string()),
        international_designator: get("OBJECT_ID").map(|f| f.value.trim().to_string()),
        norad_id: integer("NORAD_CAT_ID")?,
        classification,
        datetime,
        mean_motion_dot: float("MEAN_MOTION_DOT")?,
        mean_motion_ddot: float("MEAN_MOTION_DDOT")?,
        drag_term: float("BSTAR")?,
        element_set_number: integer("ELEMENT_SET_NO")?,
        inclination: float("INCLINATION")?,
        right_ascension: float("RA_OF_ASC_NODE")?,
        eccentricity,
        argument_of_perigee: float("ARG_OF_PERICENTER")?,
        mean_anomaly: float("MEAN_ANOMALY")?,
        mean_motion,
        revolution_number: integer("REV_AT_EPOCH")?,
        ephemeris_type: ephemeris_type as u8,
    };
    let source = match set.line {
        Some(l) => format!("{file} line {l}"),
        None => format!("{file} element set {index}"),
    };
    Sgp4Object::from_elements(source, elements)
}
