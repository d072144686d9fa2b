//! Parameter blocks of map files: all numbers between a `@marker` line and the next marker or
//! the end of the file, one row per line (thesis C.2 "Parameterblöcke").

/// One row of numbers and its line.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub line: usize,
    pub numbers: Vec<f64>,
}

/// A parameter block.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamBlock {
    pub marker: String,
    /// The line of the `@marker`.
    pub line: usize,
    pub rows: Vec<Row>,
}

/// A problem in a block, located at a line of the map file.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockError {
    pub line: usize,
    pub message: String,
}

impl BlockError {
    pub fn new(line: usize, message: impl Into<String>) -> Self {
        BlockError {
            line,
            message: message.into(),
        }
    }
}

impl ParamBlock {
    /// All rows, each with exactly `n` numbers (`what` describes a row, e.g. `r g b value`).
    pub fn rows_of(&self, n: usize, what: &str) -> Result<&[Row], BlockError> {
        if self.rows.is_empty() {
            return Err(BlockError::new(
                self.line,
                format!("block @{} is empty: expected rows of '{what}'", self.marker),
            ));
        }
        for r in &self.rows {
            if r.numbers.len() != n {
                return Err(BlockError::new(
                    r.line,
                    format!(
                        "expected {n} number{} ({what}), found {}",
                        if n == 1 { "" } else { "s" },
                        r.numbers.len()
                    ),
                ));
            }
        }
        Ok(&self.rows)
    }

    /// Exactly one row of `n` numbers.
    pub fn single_row(&self, n: usize, what: &str) -> Result<&Row, BlockError> {
        let rows = self.rows_of(n, what)?;
        if let Some(extra) = rows.get(1) {
            return Err(BlockError::new(
                extra.line,
                format!(
                    "block @{} takes one row ({what}); this is a second one",
                    self.marker
                ),
            ));
        }
        Ok(&rows[0])
    }
}

/// The block a method needs, or an error on the method line (reported by the parser).
pub fn required(block: Option<&ParamBlock>) -> Result<&ParamBlock, BlockError> {
    // The parser resolves markers before building, so a method that needs a block gets one;
    // line 0 is replaced by the method line if this ever fails.
    block.ok_or_else(|| BlockError::new(0, "expected a parameter block '@marker'"))
}

/// Absorption and emission are physical coefficients: non-negative (thesis C.2: 0 … ∞).
pub fn non_negative(row: &Row, values: &[f64], what: &str) -> Result<(), BlockError> {
    match values.iter().find(|v| **v < 0.0) {
        Some(v) => Err(BlockError::new(
            row.line,
            format!("{what} must be ≥ 0, found {v}"),
        )),
        None => Ok(()),
    }
}
