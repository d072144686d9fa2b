//! Typed errors with source locations.
//!
//! Every problem found in an input file is reported as `file:line: what was expected, what was
//! found` (thesis appendix B, docs/formats.md, "where an error is reported"), so that a user can jump straight to the line.
//! Library code never prints and never panics on bad input; it returns these values and the
//! binary decides how to show them.

use std::fmt;
use std::path::Path;

/// An error located at one line of one input file (1-based line numbers). Line 0 stands for
/// a file without lines (HDF5, netCDF): the message then names the place inside it (`dataset
/// /VTKHDF/Points: …`) and the error reads `file: message`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{}{message}", if *line == 0 { " ".to_string() } else { format!("{line}: ") })]
pub struct ParseError {
    /// The file name as the user gave it (or a label such as `<memory>`).
    pub file: String,
    /// 1-based line number (0: none, see above).
    pub line: usize,
    /// What was expected and what was found.
    pub message: String,
}

impl ParseError {
    pub fn new(file: impl Into<String>, line: usize, message: impl Into<String>) -> Self {
        ParseError {
            file: file.into(),
            line,
            message: message.into(),
        }
    }
}

/// A non-fatal remark about an input (e.g. re-oriented tetrahedra). The caller decides whether
/// and how to show it; the reader only collects them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    pub file: String,
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: warning: {}", self.file, line, self.message),
            None => write!(f, "{}: warning: {}", self.file, self.message),
        }
    }
}

/// Every error the library can return.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A located problem in an input file.
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// The operating system refused an operation on a file.
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// A request that does not fit the data it is applied to (e.g. a field number that the
    /// loaded volume does not have).
    #[error("{0}")]
    Invalid(String),
}

impl Error {
    /// Wraps an I/O error with the path it happened on.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.display().to_string(),
            source,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
