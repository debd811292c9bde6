//! Built-in scenarios: TOML files of the repository's `scenarios/` folder, and the orbit files they read,
//! embedded in the binary.

/// One built-in scenario.
#[derive(Clone, Copy, Debug)]
pub struct Builtin {
    /// Name, as given to `satflock run`.
    pub name: &'static str,
    /// The TOML text.
    pub toml: &'static str,
}

/// Every built-in scenario, in the order `satflock scenarios` lists them.
pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "free-drift",
        toml: include_str!("../../scenarios/free-drift.toml"),
    },
    Builtin {
        name: "hold",
        toml: include_str!("../../scenarios/hold.toml"),
    },
    Builtin {
        name: "hold-drag",
        toml: include_str!("../../scenarios/hold-drag.toml"),
    },
    Builtin {
        name: "drag-drift",
        toml: include_str!("../../scenarios/drag-drift.toml"),
    },
    Builtin {
        name: "dd-flock-phasing",
        toml: include_str!("../../scenarios/dd-flock-phasing.toml"),
    },
    Builtin {
        name: "dd-flock-phasing-1000",
        toml: include_str!("../../scenarios/dd-flock-phasing-1000.toml"),
    },
    Builtin {
        name: "dd-pair-keeping",
        toml: include_str!("../../scenarios/dd-pair-keeping.toml"),
    },
    Builtin {
        name: "large-swarm",
        toml: include_str!("../../scenarios/large-swarm.toml"),
    },
    Builtin {
        name: "gao-line",
        toml: include_str!("../../scenarios/gao-line.toml"),
    },
    Builtin {
        name: "gao-double-line",
        toml: include_str!("../../scenarios/gao-double-line.toml"),
    },
    Builtin {
        name: "gao-circle",
        toml: include_str!("../../scenarios/gao-circle.toml"),
    },
    Builtin {
        name: "gao-circle-drag",
        toml: include_str!("../../scenarios/gao-circle-drag.toml"),
    },
    Builtin {
        name: "gao-circle-steep",
        toml: include_str!("../../scenarios/gao-circle-steep.toml"),
    },
    Builtin {
        name: "gao-circle-large",
        toml: include_str!("../../scenarios/gao-circle-large.toml"),
    },
    Builtin {
        name: "gao-double-circle",
        toml: include_str!("../../scenarios/gao-double-circle.toml"),
    },
    Builtin {
        name: "gao-disk",
        toml: include_str!("../../scenarios/gao-disk.toml"),
    },
    Builtin {
        name: "gao-ellipse",
        toml: include_str!("../../scenarios/gao-ellipse.toml"),
    },
    Builtin {
        name: "gao-double-ellipse",
        toml: include_str!("../../scenarios/gao-double-ellipse.toml"),
    },
    Builtin {
        name: "gao-ellipse-disk",
        toml: include_str!("../../scenarios/gao-ellipse-disk.toml"),
    },
    Builtin {
        name: "gao-ellipsoid-surface",
        toml: include_str!("../../scenarios/gao-ellipsoid-surface.toml"),
    },
    Builtin {
        name: "gao-sphere-surface",
        toml: include_str!("../../scenarios/gao-sphere-surface.toml"),
    },
    Builtin {
        name: "gao-spherical-space",
        toml: include_str!("../../scenarios/gao-spherical-space.toml"),
    },
    Builtin {
        name: "gao-reconfiguration",
        toml: include_str!("../../scenarios/gao-reconfiguration.toml"),
    },
    Builtin {
        name: "ts-connectable-large",
        toml: include_str!("../../scenarios/ts-connectable-large.toml"),
    },
    Builtin {
        name: "ts-connectable-large-opp",
        toml: include_str!("../../scenarios/ts-connectable-large-opp.toml"),
    },
    Builtin {
        name: "ts-connectable-small",
        toml: include_str!("../../scenarios/ts-connectable-small.toml"),
    },
    Builtin {
        name: "ts-connectable-small-opp",
        toml: include_str!("../../scenarios/ts-connectable-small-opp.toml"),
    },
    Builtin {
        name: "ts-plane-1",
        toml: include_str!("../../scenarios/ts-plane-1.toml"),
    },
    Builtin {
        name: "ts-plane-2",
        toml: include_str!("../../scenarios/ts-plane-2.toml"),
    },
    Builtin {
        name: "ts-outage",
        toml: include_str!("../../scenarios/ts-outage.toml"),
    },
    Builtin {
        name: "es-e0",
        toml: include_str!("../../scenarios/es-e0.toml"),
    },
    Builtin {
        name: "es-e1",
        toml: include_str!("../../scenarios/es-e1.toml"),
    },
    Builtin {
        name: "es-e1-capped",
        toml: include_str!("../../scenarios/es-e1-capped.toml"),
    },
    Builtin {
        name: "es-e2a-h200",
        toml: include_str!("../../scenarios/es-e2a-h200.toml"),
    },
    Builtin {
        name: "es-e2a-h2000",
        toml: include_str!("../../scenarios/es-e2a-h2000.toml"),
    },
    Builtin {
        name: "es-e2b-1",
        toml: include_str!("../../scenarios/es-e2b-1.toml"),
    },
    Builtin {
        name: "es-e2b-2",
        toml: include_str!("../../scenarios/es-e2b-2.toml"),
    },
    Builtin {
        name: "es-e2b-3",
        toml: include_str!("../../scenarios/es-e2b-3.toml"),
    },
    Builtin {
        name: "es-e2b-4",
        toml: include_str!("../../scenarios/es-e2b-4.toml"),
    },
    Builtin {
        name: "es-e2b-2-electric",
        toml: include_str!("../../scenarios/es-e2b-2-electric.toml"),
    },
    Builtin {
        name: "es-e3a",
        toml: include_str!("../../scenarios/es-e3a.toml"),
    },
    Builtin {
        name: "es-e3b",
        toml: include_str!("../../scenarios/es-e3b.toml"),
    },
    Builtin {
        name: "es-e4",
        toml: include_str!("../../scenarios/es-e4.toml"),
    },
    Builtin {
        name: "pigeon-switching",
        toml: include_str!("../../scenarios/pigeon-switching.toml"),
    },
    Builtin {
        name: "pigeon-baseline",
        toml: include_str!("../../scenarios/pigeon-baseline.toml"),
    },
    Builtin {
        name: "omm-flock",
        toml: include_str!("../../scenarios/omm-flock.toml"),
    },
];

/// The files built-in scenarios read besides their TOML (orbit files), embedded too: (scenario, file
/// name as the scenario names it, text). A built-in's file names resolve here, not on the disk.
const FILES: &[(&str, &str, &str)] = &[(
    "omm-flock",
    "omm-flock.xml",
    include_str!("../../scenarios/omm-flock.xml"),
)];

/// The embedded file `file` of the built-in scenario `name`.
pub fn file(name: &str, file: &str) -> Option<&'static str> {
    FILES
        .iter()
        .find(|(n, f, _)| *n == name && *f == file)
        .map(|(_, _, text)| *text)
}

/// The names of the files embedded with the built-in scenario `name`.
pub fn files(name: &str) -> Vec<&'static str> {
    FILES
        .iter()
        .filter(|(n, _, _)| *n == name)
        .map(|(_, f, _)| *f)
        .collect()
}

/// The built-in scenario of that name.
pub fn find(name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|b| b.name == name)
}

/// Names of every built-in scenario.
pub fn names() -> Vec<&'static str> {
    BUILTINS.iter().map(|b| b.name).collect()
}
