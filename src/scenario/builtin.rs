//! Built-in scenarios: TOML files of the repository's `scenarios/` folder, embedded in the binary.

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
        name: "large-swarm",
        toml: include_str!("../../scenarios/large-swarm.toml"),
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
];

/// The built-in scenario of that name.
pub fn find(name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|b| b.name == name)
}

/// Names of every built-in scenario.
pub fn names() -> Vec<&'static str> {
    BUILTINS.iter().map(|b| b.name).collect()
}
