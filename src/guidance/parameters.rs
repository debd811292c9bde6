//! Shared handling of law parameter tables: partial updates from the event timeline.

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::swarm::LawError;

/// Returns `current` with the keys of `update` replaced, re-validated by deserialisation (so unknown
/// keys and wrong types are refused with the deserialiser's message).
pub fn merge_parameters<P: Serialize + DeserializeOwned>(
    law: &str,
    current: &P,
    update: &toml::Table,
) -> Result<P, LawError> {
    let invalid = |message: String| LawError::InvalidParameters {
        law: law.to_string(),
        message,
    };
    let mut table = toml::Table::try_from(current).map_err(|e| invalid(e.to_string()))?;
    for (key, value) in update {
        table.insert(key.clone(), value.clone());
    }
    P::deserialize(table).map_err(|e| invalid(e.to_string()))
}
