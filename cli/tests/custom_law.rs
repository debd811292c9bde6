//! A law of one's own in a `satflock` binary of one's own (`satflock_cli::main_with_args` with the law
//! registered, as `examples/custom_law_cli.rs` does): `compare` runs it against a built-in law from its
//! controller file `examples/custom_law.toml` and shows the headline rows it declares; scenario files
//! and law events name it as they name a built-in; bad parameters are refused with exit 2, naming the
//! file, the key and the allowed range.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use satflock::guidance::{LawRegistry, RegistryError};
use satflock::scenario::{Controller, Scenario};
use satflock_cli::compare::{compare, CompareError, CompareOptions};

// The law of `examples/custom_law.rs`, shared with the examples.
#[path = "../../examples/custom_law/centring.rs"]
mod centring;

/// A short case: 5 satellites on HCW, sampled at 1 s, 1200 s (past the law events of the controller
/// files: `examples/custom_law.toml` at 300 s, `builtin:hold` at 1000 s).
const CASE: &str = r#"
name = "centring-test"
seed = 1
duration_s = 1200.0
record_interval_s = 60.0

[dynamics]
model = "hcw"
integrator = "rk4"
step_s = 1.0

[reference]
altitude_m = 600e3
inclination_deg = 97.8

[control]
mode = "sampled"
period_s = 1.0

[satellites]
count = 5
mass_kg = 10.0
radius_m = 0.2
max_accel_mps2 = 2e-3
initial = { distribution = "sphere", radius_m = 50.0, velocity = "hcw-no-drift" }

[sensing]
range_m = 200.0

[law]
name = "hold"
stiffness_per_s2 = 1e-4
damping_per_s = 2e-2
"#;

/// The built-in laws and `centring`, installed as the process's registry (every test installs the same).
fn install() {
    registry_with_centring().install();
}

fn registry_with_centring() -> LawRegistry {
    let mut registry = LawRegistry::builtin();
    registry
        .register(centring::NAME, centring::Centring::new)
        .unwrap();
    registry
}

fn setup(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("satflock-custom-law-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("case.toml"), CASE).unwrap();
    dir
}

fn controller_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/custom_law.toml")
}

fn arg(path: &Path) -> String {
    path.display().to_string()
}

#[test]
fn compare_runs_the_registered_law_against_a_built_in_and_shows_its_headlines() {
    let dir = setup("compare");
    let out = dir.join("out");
    let code = satflock_cli::main_with_args(
        registry_with_centring(),
        [
            "satflock".to_string(),
            "compare".into(),
            arg(&dir.join("case.toml")),
            "--law".into(),
            arg(&controller_file()),
            "--law".into(),
            "builtin:hold".into(),
            "--seeds".into(),
            "1".into(),
            "--quiet".into(),
            "--out".into(),
            arg(&out),
        ],
    );
    assert_eq!(code, ExitCode::SUCCESS);
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    let row = |label: &str| -> Vec<String> {
        let line = md
            .lines()
            .find(|l| l.starts_with(&format!("| {label} |")))
            .unwrap_or_else(|| panic!("no row `{label}` in\n{md}"));
        line.split('|')
            .map(|c| c.trim().to_string())
            .filter(|c| !c.is_empty())
            .skip(1)
            .collect()
    };
    assert_eq!(row("law"), ["centring", "hold"]);
    assert_eq!(row("runs completed / not completed"), ["1 / 0", "1 / 0"]);
    // The law's own rows, with a value for the law's run and none for hold's.
    for label in [
        "centring: final centroid offset [m]",
        "centring: final worst centroid estimate error [m]",
    ] {
        let cells = row(label);
        let value: f64 = cells[0]
            .parse()
            .unwrap_or_else(|_| panic!("{label}: {cells:?}"));
        assert!(value.is_finite() && value >= 0.0, "{label}: {value}");
        assert_eq!(cells[1], "—", "{label}");
    }
    // The run's summary has them under `law`, and says which law ran.
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("runs/custom_law/seed-1/summary.json")).unwrap(),
    )
    .unwrap();
    assert!(summary["law"]["centroid_offset_m"].is_number(), "{summary}");
    assert!(
        summary["law"]["worst_estimate_error_m"].is_number(),
        "{summary}"
    );
    // The run's scenario.toml names the law with its parameters and event, and reads back.
    let written =
        std::fs::read_to_string(out.join("runs/custom_law/seed-1/scenario.toml")).unwrap();
    let again = Scenario::from_toml(&written, "scenario.toml", &dir).unwrap();
    assert_eq!(again.file.law.name(), "centring");
    again.prepare().unwrap();
}

/// The message of a comparison refused before any run (exit 2 from the command line).
/// `campaign` runs a scenario that names the registered law over seeds and a varied parameter of the
/// law: every run completes, and the table has the law's own results and the varied values.
#[test]
fn campaign_runs_the_registered_law_over_seeds_and_its_parameters() {
    let dir = setup("campaign");
    let scenario = CASE.replace(
        "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2\n",
        "[law]\nname = \"centring\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2\ndither_m = 0.0\n",
    );
    assert_ne!(scenario, CASE);
    std::fs::write(dir.join("case.toml"), scenario).unwrap();
    std::fs::write(
        dir.join("campaign.toml"),
        "scenario = \"case.toml\"\nseeds = [1, 2]\noutcomes = [\"law.centroid_offset_m\"]\n\
         [vary]\n\"law.damping_per_s\" = [0.01, 0.02]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let code = satflock_cli::main_with_args(
        registry_with_centring(),
        [
            "satflock".to_string(),
            "campaign".into(),
            arg(&dir.join("campaign.toml")),
            "--quiet".into(),
            "--fail-on-run-failure".into(),
            "--out".into(),
            arg(&out),
        ],
    );
    assert_eq!(code, ExitCode::SUCCESS);
    let table = satflock::output::RunTable::read_parquet(&out.join("campaign.parquet")).unwrap();
    assert_eq!(table.rows(), 4);
    assert_eq!(
        table.text("status").unwrap(),
        ["completed", "completed", "completed", "completed"]
    );
    let offsets = table.numbers("law.centroid_offset_m").unwrap();
    assert!(
        offsets.iter().all(|v| v.is_finite() && *v >= 0.0),
        "{offsets:?}"
    );
    let dampings = table.numbers("parameter.law.damping_per_s").unwrap();
    assert_eq!(dampings, [0.01, 0.01, 0.02, 0.02]);
}

fn refused(dir: &Path, controller: &str) -> String {
    install();
    let file = dir.join("bad.toml");
    std::fs::write(&file, controller).unwrap();
    let options = CompareOptions {
        case: arg(&dir.join("case.toml")),
        laws: vec![arg(&file), "builtin:hold".into()],
        seeds: Some(vec![1]),
        out: dir.join("out"),
        jobs: 1,
        ..CompareOptions::default()
    };
    match compare(&options) {
        Err(CompareError::Input(message)) => message,
        other => panic!("{controller}: {:?}", other.map(|r| r.markdown)),
    }
}

#[test]
fn bad_parameters_of_the_registered_law_are_refused_naming_file_key_and_range() {
    let dir = setup("refused");
    let bad = dir.join("bad.toml");
    let message = refused(
        &dir,
        "[law]\nname = \"centring\"\nstiffness_per_s2 = -1.0\ndamping_per_s = 0.02\n",
    );
    for part in [
        arg(&bad).as_str(),
        "key `law`",
        "law `centring`",
        "key `stiffness_per_s2`: -1 is out of range (allowed: finite, > 0)",
    ] {
        assert!(message.contains(part), "`{part}` not in: {message}");
    }
    // A set-law-parameters event of the controller: its merged parameters are checked too.
    let message = refused(
        &dir,
        "[law]\nname = \"centring\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 0.02\n\n\
         [[events]]\ntime_s = 10.0\naction = \"set-law-parameters\"\nparameters = { dither_m = -2.0 }\n",
    );
    for part in [
        "key `events[0].parameters`",
        "key `dither_m`: -2 is out of range (allowed: finite, >= 0)",
    ] {
        assert!(message.contains(part), "`{part}` not in: {message}");
    }
    // A misspelt key: refused when the file is read, naming the key and the keys the law takes.
    let message = refused(
        &dir,
        "[law]\nname = \"centring\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 0.02\ngain = 1.0\n",
    );
    for part in [
        "unknown field `gain`",
        "stiffness_per_s2",
        "dither_m",
        "line 5",
    ] {
        assert!(message.contains(part), "`{part}` not in: {message}");
    }
    // An unknown law: the message lists the registered law with the built-ins.
    let message = refused(&dir, "[law]\nname = \"centering\"\n");
    assert!(
        message.contains("unknown variant `centering`")
            && message.contains("`hold`, ")
            && message.contains("`centring`"),
        "{message}"
    );
    // And from the command line: exit 2, nothing run.
    let code = satflock_cli::main_with_args(
        registry_with_centring(),
        [
            "satflock".to_string(),
            "run".into(),
            arg(&dir.join("case.toml")),
            "--law".into(),
            arg(&bad),
            "--quiet".into(),
            "--out".into(),
            arg(&dir.join("run")),
        ],
    );
    assert_eq!(code, ExitCode::from(2));
}

#[test]
fn a_scenario_names_the_registered_law_and_its_events_as_a_built_in() {
    install();
    let dir = setup("scenario");
    let text = CASE.replace(
        "[law]\nname = \"hold\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2\n",
        "[law]\nname = \"centring\"\nstiffness_per_s2 = 1e-4\ndamping_per_s = 2e-2\n\n\
         [[events]]\ntime_s = 50.0\naction = \"set-law-parameters\"\nparameters = { dither_m = 0.5 }\n",
    );
    assert!(text.contains("centring"));
    let scenario = Scenario::from_toml(&text, "centring.toml", &dir).unwrap();
    scenario.prepare().unwrap();
    // An event with a value out of range is refused at load time, naming the event and the range.
    let bad = text.replace("dither_m = 0.5", "dither_m = -0.5");
    let Err(error) = Scenario::from_toml(&bad, "centring.toml", &dir)
        .unwrap()
        .prepare()
    else {
        panic!("a dither_m < 0 set by an event was accepted");
    };
    let error = error.to_string();
    for part in [
        "centring.toml",
        "events[0]",
        "key `dither_m`: -0.5 is out of range (allowed: finite, >= 0)",
    ] {
        assert!(error.contains(part), "`{part}` not in: {error}");
    }
    // A controller file naming the law steers a built-in case.
    let controller = Controller::load(&arg(&controller_file())).unwrap();
    assert_eq!(controller.file.law.name(), "centring");
    Scenario::load("hold")
        .unwrap()
        .with_controller(&controller)
        .prepare()
        .unwrap();
}

#[test]
fn the_registry_refuses_taken_and_invalid_names() {
    let mut registry = registry_with_centring();
    assert!(matches!(
        registry.register("hold", centring::Centring::new),
        Err(RegistryError::NameTaken { .. })
    ));
    assert!(matches!(
        registry.register(centring::NAME, centring::Centring::new),
        Err(RegistryError::NameTaken { .. })
    ));
    assert!(matches!(
        registry.register("Centring 2", centring::Centring::new),
        Err(RegistryError::InvalidName { .. })
    ));
    let names = registry.names();
    assert_eq!(names.first(), Some(&"none"));
    assert_eq!(names.last(), Some(&"centring"));
}
