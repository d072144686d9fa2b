//! `rank`: where this process stands in a distributed session (docs/distributed.md).

use super::{Call, CommandInfo};
use crate::script::Context;

pub const RANK: CommandInfo = CommandInfo {
    name: "rank",
    usage: "?count?",
    summary: "this process's rank in a distributed session (0 … count − 1; 0 in one process); 'rank count': the number of ranks",
    details: "Under 'mpirun -np N vorang script.tcl' every rank runs the whole script and renders its share of the volume; only rank 0 writes images and prints. A script that does something once (e.g. 'puts') can ask 'if {[rank] == 0} {…}'. A script must not give different ranks different commands that render or load: they would wait for each other.",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=1)?;
        let (rank, count) = s.session.rank();
        match c.args().first().map(String::as_str) {
            None => Ok(rank.to_string()),
            Some("count") => Ok(count.to_string()),
            Some(other) => Err(format!("rank: expected count or nothing, found '{other}'")),
        }
    },
};
