//! Array lengths in TOML files, checked strictly: the toml crate's document deserializer
//! fills a fixed-size array (`[f64; 3]`) from the first elements of a longer TOML array and
//! drops the rest without a word, while its value deserializer refuses the surplus. Files are
//! read through the first (its errors carry line numbers) and then through the second, so a
//! surplus element is an error naming the key.

use serde::de::DeserializeOwned;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize)]
    #[allow(dead_code)]
    struct Pose {
        xy: [f64; 2],
    }

    #[test]
    fn a_surplus_element_names_its_key() {
        assert!(check_lengths::<Pose>("xy = [1.0, 2.0]").is_ok());
        let e = check_lengths::<Pose>("xy = [1.0, 2.0, 3.0]").unwrap_err();
        assert!(e.starts_with("xy: invalid length 3"), "{e}");
    }
}
