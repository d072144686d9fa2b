//! Tab completion at the prompt: command names where a command starts (the
//! line's first word, or after `;`, `[` or `{`), file names elsewhere (the prompt falls back to
//! rustyline's file name completer).

/// Where the word ending at byte `pos` of `line` starts, and whether it is in command
/// position.
pub fn word_at(line: &str, pos: usize) -> (usize, bool) {
    let before = &line[..pos];
    let start = before
        .rfind(|c: char| c.is_whitespace() || matches!(c, ';' | '[' | '{' | '"'))
        .map_or(0, |i| {
            i + before[i..].chars().next().map_or(1, char::len_utf8)
        });
    let prefix = before[..start].trim_end();
    let command = prefix.is_empty() || prefix.ends_with([';', '[', '{']);
    (start, command)
}

/// The command names starting with the word at `pos`, sorted, if the word is in command
/// position and not empty; `None` where file names should be completed instead.
pub fn commands_at<'a>(
    line: &str,
    pos: usize,
    names: impl IntoIterator<Item = &'a str>,
) -> Option<(usize, Vec<String>)> {
    let (start, command) = word_at(line, pos);
    let word = &line[start..pos];
    if !command || word.is_empty() {
        return None;
    }
    let mut found: Vec<String> = names
        .into_iter()
        .filter(|n| n.starts_with(word))
        .map(str::to_string)
        .collect();
    found.sort();
    found.dedup();
    Some((start, found))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_complete_where_commands_start() {
        let names = [
            "render_btf",
            "render_ftb",
            "colormap",
            "volume",
            "vol_rotate",
        ];
        let at_end = |line: &str| commands_at(line, line.len(), names);
        assert_eq!(
            at_end("rend"),
            Some((0, vec!["render_btf".into(), "render_ftb".into()]))
        );
        assert_eq!(
            at_end("volume a.hmesh; col"),
            Some((16, vec!["colormap".into()]))
        );
        assert_eq!(
            at_end("for {set i 0} {$i < 3} {incr i} {vol"),
            Some((33, vec!["vol_rotate".into(), "volume".into()]))
        );
        assert_eq!(at_end("set x [vol").unwrap().0, 7);
        // Arguments are file names.
        assert_eq!(at_end("volume exa"), None);
        assert_eq!(commands_at("", 0, names), None);
    }
}
