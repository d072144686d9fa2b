//! The reference of everything a script names, generated from the tables the program itself
//! uses: commands ([`COMMANDS`]), methods and integration rules, colour and opacity shading
//! methods, field interpolators. `docs/commands.md` is this text; a test fails when the two
//! drift apart (`VORANG_BLESS=1 cargo test --test docs` rewrites the file).

use std::fmt::Write;

use super::COMMANDS;

/// The reference as Markdown.
pub fn markdown() -> String {
    let mut s = String::new();
    let mut line = |text: &str| {
        s.push_str(text);
        s.push('\n');
    };
    line("# Script commands and names");
    line("");
    line("Generated from the program's own tables by `vorang::script::reference::markdown`");
    line("(`VORANG_BLESS=1 cargo test --test docs` rewrites it; the test fails when it is out of");
    line("date). Every command is also described by `help NAME` at the prompt or in a script.");
    line("");
    line("## Commands");
    line("");
    for c in COMMANDS {
        if c.usage.is_empty() {
            line(&format!("### `{}`", c.name));
        } else {
            line(&format!("### `{} {}`", c.name, c.usage));
        }
        line("");
        line(&format!("{}.", capitalise(c.summary)));
        if !c.details.is_empty() {
            line("");
            line(c.details);
        }
        line("");
    }
    line("## Methods (`method`)");
    line("");
    line("| method | parameters | what it does |");
    line("|---|---|---|");
    for m in vorang::render::METHODS {
        line(&format!(
            "| `{}` | `{}` | {} |",
            m.name,
            m.usage,
            cell(m.summary)
        ));
    }
    line("");
    line("The thesis's short names `interpolCoeff` and `interpolColor` are accepted too.");
    line("");
    line("## Integration rules (`method exact RULE …`, `method interpolateCoeff RULE …`)");
    line("");
    line("| rule | what it does |");
    line("|---|---|");
    for r in vorang::integrate::RULES {
        line(&format!("| `{}` | {} |", r.name, cell(r.summary)));
    }
    line("");
    line("## Colour shading methods (colormap files)");
    line("");
    line("| method | parameter block | what it does |");
    line("|---|---|---|");
    for m in vorang::mapping::COLOR_METHODS {
        line(&format!(
            "| `{}` | {} | {} |",
            m.name,
            cell(m.params),
            cell(m.summary)
        ));
    }
    line("");
    line(vorang::mapping::COMPLEX_HELP);
    line("");
    line("## Opacity shading methods (alphamap files)");
    line("");
    line("| method | parameter block | what it does |");
    line("|---|---|---|");
    for m in vorang::mapping::ALPHA_METHODS {
        line(&format!(
            "| `{}` | {} | {} |",
            m.name,
            cell(m.params),
            cell(m.summary)
        ));
    }
    line("");
    line("## Field interpolators (HyperMesh `Field` lines)");
    line("");
    line("| interpolator | written | what it does |");
    line("|---|---|---|");
    for f in vorang::field::INTERPOLATORS {
        let mut row = String::new();
        let _ = write!(
            row,
            "| `{}` | `{}` | {} |",
            f.name,
            f.signature,
            cell(f.summary)
        );
        line(&row);
    }
    s
}

/// Text for a table cell: no line breaks or bars.
fn cell(text: &str) -> String {
    text.replace('\n', " ").replace('|', "\\|")
}

fn capitalise(text: &str) -> String {
    let mut c = text.chars();
    match c.next() {
        Some(first) => first.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}
