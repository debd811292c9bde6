//! TOML values <-> Python objects, for scenarios and campaigns given as dicts.
//!
//! TOML → Python: strings, integers, floats, booleans, arrays (lists) and tables (dicts); a date-time
//! becomes its RFC 3339 text. Python → TOML: `bool`, `int` (64-bit), `float`, `str`, `list`/`tuple`,
//! `dict` with string keys, and numpy scalars (through their `item()`); `None` has no TOML form and is
//! refused.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A TOML value as a Python object.
pub fn toml_to_py<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(toml_to_py(py, item)?)?;
            }
            list.into_any()
        }
        toml::Value::Table(table) => table_to_py(py, table)?.into_any(),
    })
}

/// A TOML table as a Python dict.
pub fn table_to_py<'py>(py: Python<'py>, table: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, value) in table {
        dict.set_item(key, toml_to_py(py, value)?)?;
    }
    Ok(dict)
}

/// A Python object as a TOML value; the error says what was found where (`at`: the dotted key).
pub fn py_to_toml(obj: &Bound<'_, PyAny>, at: &str) -> Result<toml::Value, String> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(
            obj.extract::<bool>().map_err(|e| e.to_string())?,
        ));
    }
    if obj.is_instance_of::<PyInt>() {
        return obj
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| format!("`{at}`: the integer {obj} does not fit 64 bits"));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(
            obj.extract::<f64>().map_err(|e| e.to_string())?,
        ));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(
            obj.extract::<String>().map_err(|e| e.to_string())?,
        ));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        return dict_to_table(dict, at).map(toml::Value::Table);
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (k, item) in obj.try_iter().map_err(|e| e.to_string())?.enumerate() {
            let item = item.map_err(|e| e.to_string())?;
            items.push(py_to_toml(&item, &format!("{at}.{k}"))?);
        }
        return Ok(toml::Value::Array(items));
    }
    if obj.is_none() {
        return Err(format!(
            "`{at}` is None, which a scenario cannot hold (leave the key out for its default)"
        ));
    }
    // numpy scalars (np.float64, np.int32, np.bool_) and 0-d arrays: their Python value.
    if obj.hasattr("item").unwrap_or(false) && obj.hasattr("dtype").unwrap_or(false) {
        if let Ok(item) = obj.call_method0("item") {
            if !item.hasattr("dtype").unwrap_or(false) {
                return py_to_toml(&item, at);
            }
        }
    }
    let type_name = obj
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into());
    Err(format!(
        "`{at}` is a {type_name}, which a scenario cannot hold (allowed: bool, int, float, str, list, \
         dict, numpy scalars)"
    ))
}

/// A Python dict with string keys as a TOML table.
pub fn dict_to_table(dict: &Bound<'_, PyDict>, at: &str) -> Result<toml::Table, String> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| format!("`{at}`: every key of a dict must be a str, found {key}"))?;
        let path = if at.is_empty() {
            key.clone()
        } else {
            format!("{at}.{key}")
        };
        table.insert(key, py_to_toml(&value, &path)?);
    }
    Ok(table)
}
