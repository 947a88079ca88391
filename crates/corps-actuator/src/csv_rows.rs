//! Numeric CSV files with a header: the columns are found by name, in any order; blank lines
//! are skipped; every error names its line.

use crate::error::ActuatorError;

/// Calls `row(line, values)` for each data line of `text` with the values of `columns` (by
/// header name) in that order; `line` counts from 1 as an editor does.
pub(crate) fn read_rows<const N: usize>(
    text: &str,
    columns: [&str; N],
    mut row: impl FnMut(usize, [f64; N]) -> Result<(), ActuatorError>,
) -> Result<(), ActuatorError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .ok_or_else(|| ActuatorError::Data("the file is empty".into()))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [0usize; N];
    for (i, c) in columns.iter().enumerate() {
        index[i] = names.iter().position(|n| n == c).ok_or_else(|| {
            ActuatorError::Data(format!(
                "no column `{c}` in the header (expected {})",
                columns.join(",")
            ))
        })?;
    }
    for (line, text) in lines {
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        let mut v = [0.0; N];
        for (i, &col) in index.iter().enumerate() {
            let field = fields.get(col).ok_or_else(|| {
                ActuatorError::Data(format!(
                    "line {}: {} fields, {} expected",
                    line + 1,
                    fields.len(),
                    names.len()
                ))
            })?;
            v[i] = field.parse().map_err(|_| {
                ActuatorError::Data(format!(
                    "line {}: `{field}` is not a number ({})",
                    line + 1,
                    columns[i]
                ))
            })?;
        }
        row(line + 1, v)?;
    }
    Ok(())
}
