//! Strict reading of TOML configuration text: unknown keys are errors (the types say
//! `deny_unknown_fields`), an array longer than the fixed-size field it fills is an error, and
//! every error is one line, `line N: key.path: message`.
//!
//! The toml crate's document deserializer fills a fixed-size array (`[f64; 3]`) from the first
//! elements of a longer TOML array and drops the rest; its value deserializer refuses the
//! surplus. Text is read through the first (its errors carry line numbers), then through the
//! second. [`merge`] lays one table over another.

use serde::de::DeserializeOwned;

/// Parses `text` as a `T`; the error is one line naming the line and the key.
pub fn parse<T: DeserializeOwned>(text: &str) -> Result<T, String> {
    let de = toml::Deserializer::parse(text).map_err(|e| one_line(text, &e, ""))?;
    let value: T = serde_path_to_error::deserialize(de)
        .map_err(|e| one_line(text, e.inner(), &e.path().to_string()))?;
    check_lengths::<T>(text)?;
    Ok(value)
}

/// `Err("key.path: invalid length …")` when `text` holds an array longer than the field of
/// `T` it fills; `Ok` otherwise (other errors are the first reading's to report).
pub fn check_lengths<T: DeserializeOwned>(text: &str) -> Result<(), String> {
    let Ok(table) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    match serde_path_to_error::deserialize::<_, T>(toml::Value::Table(table)) {
        Err(e) if e.inner().message().contains("invalid length") => {
            Err(format!("{}: {}", e.path(), e.inner().message().trim()))
        }
        _ => Ok(()),
    }
}

/// `line N: key.path: message`, with the text a syntax error points at.
fn one_line(text: &str, e: &toml::de::Error, path: &str) -> String {
    let span = e
        .span()
        .map(|s| s.start.min(text.len())..s.end.min(text.len()));
    let line = span
        .as_ref()
        .map(|s| format!("line {}: ", text[..s.start].matches('\n').count() + 1))
        .unwrap_or_default();
    let key = if path.is_empty() || path == "." {
        String::new()
    } else {
        format!("{path}: ")
    };
    let mut message = e.message().trim().replace('\n', " ");
    // Syntax errors (no key path) show the text they point at, e.g. a duplicate key.
    if let Some(at) = span.map(|s| text[s].trim()) {
        if key.is_empty() && !at.is_empty() && at.len() <= 40 && !at.contains('\n') {
            message = format!("{message} `{at}`");
        }
    }
    format!("{line}{key}{message}")
}

/// `over`'s keys into `base`: tables merged key by key, any other value replaced (a
/// description extending another, a scenario's `controller.set` over a gains file).
pub fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (key, value) in over {
        match (base.get_mut(key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Pose {
        xy: [f64; 2],
    }

    #[test]
    fn a_surplus_element_names_its_key() {
        assert!(check_lengths::<Pose>("xy = [1.0, 2.0]").is_ok());
        let e = check_lengths::<Pose>("xy = [1.0, 2.0, 3.0]").unwrap_err();
        assert!(e.starts_with("xy: invalid length 3"), "{e}");
        let e = parse::<Pose>("xy = [1.0, 2.0, 3.0]").unwrap_err();
        assert!(e.starts_with("xy: invalid length 3"), "{e}");
    }

    #[test]
    fn errors_name_the_line_and_the_key() {
        let e = parse::<Pose>("\nxz = [1.0, 2.0]").unwrap_err();
        assert!(e.starts_with("line 2: ") && e.contains("xz"), "{e}");
        let e = parse::<Pose>("xy = [1.0, \"a\"]").unwrap_err();
        assert!(e.contains("xy"), "{e}");
    }
}
