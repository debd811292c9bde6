//! TOML values <-> Python objects, for scenarios and campaigns given as dicts.
//!
//! TOML → Python: strings, integers, floats, booleans, arrays (lists) and tables (dicts); a date-time
//! becomes its RFC 3339 text. Python → TOML: `bool`, `int` (64-bit), `float`, `str`, `list`/`tuple`,
//! `dict` with string keys, numpy arrays (through their `tolist()`: nested lists) and numpy scalars
//! (through their `item()`); `None` has no TOML form and is
//! refused, and so are a dict or list that contains itself and nesting deeper than [`MAX_DEPTH`].

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

/// Deepest nesting of dicts and lists a scenario or campaign given as a dict may have (a scenario file
/// nests a few levels; a deeper structure is a mistake, and would exhaust the stack).
pub const MAX_DEPTH: usize = 64;

/// A Python object as a TOML value; the error says what was found where (`at`: the dotted key). Nesting
/// beyond [`MAX_DEPTH`] and a dict or list that contains itself are refused.
pub fn py_to_toml(obj: &Bound<'_, PyAny>, at: &str) -> Result<toml::Value, String> {
    convert(obj, at, &mut Vec::new())
}

/// [`py_to_toml`] with the containers on the path to `obj` (their addresses), outermost first.
fn convert(obj: &Bound<'_, PyAny>, at: &str, path: &mut Vec<usize>) -> Result<toml::Value, String> {
    let is_container = obj.is_instance_of::<PyDict>()
        || obj.is_instance_of::<PyList>()
        || obj.is_instance_of::<PyTuple>();
    if !is_container {
        return leaf(obj, at, path);
    }
    let address = obj.as_ptr() as usize;
    let shown = if at.is_empty() { "the top level" } else { at };
    if path.contains(&address) {
        return Err(format!(
            "`{shown}` contains itself (a dict or list that holds itself has no TOML form)"
        ));
    }
    if path.len() >= MAX_DEPTH {
        return Err(format!(
            "`{shown}` is nested deeper than {MAX_DEPTH} levels of dicts and lists (allowed: at most \
             {MAX_DEPTH})"
        ));
    }
    path.push(address);
    let value = if let Ok(dict) = obj.cast::<PyDict>() {
        table(dict, at, path).map(toml::Value::Table)
    } else {
        let mut items = Vec::new();
        let iter = obj.try_iter().map_err(|e| e.to_string())?;
        for (k, item) in iter.enumerate() {
            let item = item.map_err(|e| e.to_string())?;
            items.push(convert(&item, &format!("{at}.{k}"), path)?);
        }
        Ok(toml::Value::Array(items))
    };
    path.pop();
    value
}

/// A Python object that is not a dict, list or tuple as a TOML value.
fn leaf(obj: &Bound<'_, PyAny>, at: &str, path: &mut Vec<usize>) -> Result<toml::Value, String> {
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
    if obj.is_none() {
        return Err(format!(
            "`{at}` is None, which a scenario cannot hold (leave the key out for its default)"
        ));
    }
    // numpy arrays of one or more dimensions (e.g. an (N, 6) array of EME2000 states): their nested
    // lists, converted item by item like any list.
    let ndim = obj
        .getattr("ndim")
        .ok()
        .and_then(|n| n.extract::<usize>().ok());
    if obj.hasattr("dtype").unwrap_or(false) && ndim.is_some_and(|n| n >= 1) {
        if let Ok(list) = obj.call_method0("tolist") {
            if list.is_instance_of::<PyList>() {
                return convert(&list, at, path);
            }
        }
    }
    // numpy scalars (np.float64, np.int32, np.bool_) and 0-d arrays: their Python value.
    if obj.hasattr("item").unwrap_or(false) && obj.hasattr("dtype").unwrap_or(false) {
        if let Ok(item) = obj.call_method0("item") {
            if !item.hasattr("dtype").unwrap_or(false) {
                return convert(&item, at, path);
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
         dict, numpy arrays and scalars)"
    ))
}

/// A Python dict with string keys as a TOML table (nesting and cycles refused as by [`py_to_toml`]).
pub fn dict_to_table(dict: &Bound<'_, PyDict>, at: &str) -> Result<toml::Table, String> {
    match convert(dict.as_any(), at, &mut Vec::new())? {
        toml::Value::Table(t) => Ok(t),
        other => Err(format!("`{at}` is a {}, not a table", other.type_str())),
    }
}

/// The entries of `dict` (on `path`, see [`convert`]) as a TOML table.
fn table(
    dict: &Bound<'_, PyDict>,
    at: &str,
    stack: &mut Vec<usize>,
) -> Result<toml::Table, String> {
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
        table.insert(key, convert(&value, &path, stack)?);
    }
    Ok(table)
}
