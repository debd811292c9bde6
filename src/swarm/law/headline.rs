//! A law's headline outcomes: the few of its `summary.json` results ([`super::Reports::results`])
//! that say how well it did, each with a label, a unit and which way is better. `satflock compare`
//! shows them as rows of its side-by-side table, after the outcomes every run has, so a law declares
//! its own rows and no tool needs to know law names.

/// Which way an outcome is better.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Better {
    /// Smaller values are better (a time to converge, a residual, a Δv).
    Lower,
    /// Larger values are better (an order parameter, a miss distance).
    Higher,
}

impl Better {
    /// `"lower"` or `"higher"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Better::Lower => "lower",
            Better::Higher => "higher",
        }
    }
}

/// One headline outcome of a law: a key of its results (`summary.json` `law.NAME`, the outcome column
/// `law.NAME` of `compare.parquet` and `campaign.parquet`), how to label it and its unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Headline {
    /// The key in the law's results (without the `law.` prefix), e.g. `time_to_shape_s`.
    pub name: &'static str,
    /// What it is, in words, e.g. `time to shape`.
    pub label: &'static str,
    /// Its unit as shown in brackets, e.g. `s`, `m`, `-` for a number without unit.
    pub unit: &'static str,
    /// Which way is better.
    pub better: Better,
}

impl Headline {
    /// A headline outcome (usable in a `const` list).
    pub const fn new(
        name: &'static str,
        label: &'static str,
        unit: &'static str,
        better: Better,
    ) -> Self {
        Self {
            name,
            label,
            unit,
            better,
        }
    }

    /// The outcome column of a table of runs: `law.NAME`.
    pub fn column(&self) -> String {
        format!("law.{}", self.name)
    }

    /// The row label of a comparison: `LAW: LABEL [UNIT]`.
    pub fn row_label(&self, law: &str) -> String {
        format!("{law}: {} [{}]", self.label, self.unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_headline_names_its_column_and_row() {
        let h = Headline::new("time_to_shape_s", "time to shape", "s", Better::Lower);
        assert_eq!(h.column(), "law.time_to_shape_s");
        assert_eq!(h.row_label("bifurcating"), "bifurcating: time to shape [s]");
        assert_eq!(h.better.as_str(), "lower");
    }
}
