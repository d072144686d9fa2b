//! Where a front end's messages go: the render line and notes to standard output, warnings to
//! standard error — or into a buffer for tests. The core returns its messages as values
//! ([`vorang::Notice`]); these are the Tcl front ends' ways of showing them.

/// Where messages go: the render line and notes to standard output, warnings to standard
/// error — or into a buffer for tests.
pub trait Reporter {
    fn info(&mut self, text: &str);
    fn warn(&mut self, text: &str);
    /// Render progress (`done` of `total` tiles), called from the render threads' side.
    fn progress(&self, _done: usize, _total: usize) {}
}

/// Prints to the terminal, with a progress bar on standard error if it is a terminal.
#[derive(Debug, Default)]
pub struct Terminal;

impl Reporter for Terminal {
    fn info(&mut self, text: &str) {
        println!("{text}");
    }
    fn warn(&mut self, text: &str) {
        eprintln!("{text}");
    }
}

/// Collects messages (for tests and embedding).
#[derive(Debug, Default, Clone)]
pub struct Collect {
    pub info: Vec<String>,
    pub warnings: Vec<String>,
}

impl Reporter for Collect {
    fn info(&mut self, text: &str) {
        self.info.push(text.to_string());
    }
    fn warn(&mut self, text: &str) {
        self.warnings.push(text.to_string());
    }
}

/// Says nothing: a rank of a distributed session other than rank 0, whose messages rank 0
/// already shows (docs/distributed.md).
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;

impl Reporter for Quiet {
    fn info(&mut self, _: &str) {}
    fn warn(&mut self, _: &str) {}
}
