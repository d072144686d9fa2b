//! MPVO's topological sort on every core: the cells are placed a *level* at a time.
//!
//! Level 0 holds the cells with no neighbour behind them; level `l + 1` the cells whose last
//! neighbour behind was placed in level `l`. Across every face the cell in front is in a later
//! level, so the cells ordered by level are a visibility order, and the order inside a level
//! does not matter: no two cells of a level share a face, and along a ray through a convex mesh
//! the cells a ray crosses are face-adjacent, each in a later level than the one before. That is
//! the order a first-in-first-out Kahn sort produces, with its own order inside each level.
//!
//! Each cell belongs to one of at most [`CHUNKS`] chunks (ranges of consecutive cell numbers,
//! dealt to the threads round-robin) and each chunk to one thread. Only that thread reads or
//! writes the chunk's bytes of the relation, so the counts of neighbours behind need no atomic
//! read-modify-write, which made a shared-count version slower than one thread
//! (docs/performance.md). A cell in front of a
//! cell of another chunk is told by a message, delivered after the threads have met at the end
//! of the level. The order inside a level is the chunks' order, each chunk's cells in the order
//! they became ready, messages in the order of their sending chunk: the same for any number of
//! threads, so the image does not depend on it even where the order matters (a visibility
//! cycle, settled per pixel).

use rayon::prelude::*;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use super::mpvo::{QUEUED, behind_count, farthest_waiting, release};
use super::{Order, SortInput};

/// The number of chunks: enough for a level's cells to spread evenly over many threads.
const CHUNKS: usize = 64;
/// How long a thread spins at a meeting before it yields its core, in pauses (a few
/// microseconds): a level takes tens of microseconds, and a thread that spins while the one it
/// waits for has no core (more threads than cores) holds up the whole sort.
const SPINS: u32 = 64;
/// How many cells ahead the neighbour table's rows are fetched.
const AHEAD: usize = 16;

/// The chunks are ranges of consecutive cell numbers, `1 << shift` long: a thread then walks its
/// part of the neighbour table in one direction per level, page by page, as one thread walking
/// the whole level would (chunks dealt out in small blocks were slower: every chunk walked the
/// whole table).
#[derive(Clone, Copy)]
struct Chunking {
    shift: u32,
    count: usize,
}

impl Chunking {
    fn new(cells: usize) -> Chunking {
        let shift = cells.div_ceil(CHUNKS).next_power_of_two().trailing_zeros();
        Chunking {
            shift,
            count: cells.div_ceil(1 << shift),
        }
    }

    #[inline]
    fn of(self, cell: u32) -> usize {
        (cell >> self.shift) as usize
    }

    /// The cell's place in its chunk.
    #[inline]
    fn within(self, cell: u32) -> usize {
        (cell & ((1 << self.shift) - 1)) as usize
    }
}

/// What a placed cell tells the cells in front of it besides that it is placed: nothing for
/// MPVO, the bound for MPVONC's order ([`super::farthest`]).
pub(super) trait Carry: Copy + Default + Send + Sync {
    /// `self`, of a cell still waiting, told `from` by a cell behind it.
    fn take(&mut self, from: Self);
}

impl Carry for () {
    #[inline]
    fn take(&mut self, _: ()) {}
}

/// Whether a cell carries anything: MPVO's sort then never touches the carried values, not even
/// to check an index.
#[inline(always)]
fn carries<C>() -> bool {
    size_of::<C>() > 0
}

/// The value `carried[i]` (nothing to read where nothing is carried).
#[inline(always)]
fn carried_at<C: Carry>(carried: &[C], i: usize) -> C {
    if carries::<C>() {
        carried[i]
    } else {
        C::default()
    }
}

/// A chunk's cells in the order it placed them, in its stretch of one buffer for all chunks
/// (a chunk places each of its cells once: the stretch is as long as the chunk).
struct Placed<'a> {
    cells: &'a mut [u32],
    len: usize,
}

impl Placed<'_> {
    #[inline]
    fn push(&mut self, cell: u32) {
        self.cells[self.len] = cell;
        self.len += 1;
    }

    #[inline]
    fn len(&self) -> usize {
        self.len
    }
}

impl std::ops::Index<usize> for Placed<'_> {
    type Output = u32;
    #[inline]
    fn index(&self, i: usize) -> &u32 {
        debug_assert!(i < self.len, "a cell not placed yet");
        &self.cells[i]
    }
}

/// One chunk: its cells' bytes of the relation and what they carry, its cells placed so far,
/// in order, and how many it placed in each level.
struct Chunk<'a, C> {
    state: &'a mut [u8],
    carried: &'a mut [C],
    placed: Placed<'a>,
    /// Where the current level starts in `placed`.
    begin: usize,
    /// (level, count) for each level in which this chunk placed cells.
    levels: Vec<(u32, u32)>,
}

impl<C> Default for Chunk<'_, C> {
    fn default() -> Self {
        Chunk {
            state: &mut [],
            carried: &mut [],
            placed: Placed {
                cells: &mut [],
                len: 0,
            },
            begin: 0,
            levels: Vec::new(),
        }
    }
}

/// Cells one thread tells another, and what they are told: those of each sending chunk, in
/// chunk order.
struct Mail<C> {
    cells: Vec<u32>,
    carried: Vec<C>,
    /// (sending chunk, end of its cells in `cells`).
    ends: Vec<(usize, usize)>,
}

impl<C> Default for Mail<C> {
    fn default() -> Self {
        Mail {
            cells: Vec::new(),
            carried: Vec::new(),
            ends: Vec::new(),
        }
    }
}

/// What the threads share: a barrier that also sums a number over them, and the mail, one box
/// per level parity, sender and receiver (a box is written in one level and read in the next
/// half of it, while the other parity's boxes are being written).
struct Team<C> {
    threads: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    /// Sums of three consecutive meetings, reused in turn.
    sums: [AtomicUsize; 3],
    mail: Vec<Mutex<Mail<C>>>,
    /// A thread panicked: the others stop waiting for it.
    broken: AtomicBool,
}

/// Marks the team broken when its thread unwinds.
struct Bail<'a, C>(&'a Team<C>);

impl<C> Drop for Bail<'_, C> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.broken.store(true, Ordering::Release);
        }
    }
}

impl<C> Team<C> {
    fn new(threads: usize) -> Team<C> {
        Team {
            threads,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            sums: Default::default(),
            mail: (0..2 * threads * threads)
                .map(|_| Mutex::default())
                .collect(),
            broken: AtomicBool::new(false),
        }
    }

    fn mail(&self, parity: usize, from: usize, to: usize) -> MutexGuard<'_, Mail<C>> {
        let i = (parity * self.threads + from) * self.threads + to;
        // A box is only ever held by one thread between two meetings: never poisoned in use.
        self.mail[i].lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Waits for every thread of meeting `meeting` and returns the sum of their `value`s. A
    /// thread spins briefly, then yields: the levels are short, and a thread that sleeps would
    /// cost more than the level.
    fn meet(&self, meeting: usize, value: usize) -> usize {
        let sum = &self.sums[meeting % 3];
        sum.fetch_add(value, Ordering::AcqRel);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            // Everyone has read the sum of two meetings ago: its slot is the next one's.
            self.sums[(meeting + 1) % 3].store(0, Ordering::Relaxed);
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.store(meeting + 1, Ordering::Release);
        } else {
            let mut spins = 0u32;
            while self.generation.load(Ordering::Acquire) == meeting {
                assert!(
                    !self.broken.load(Ordering::Acquire),
                    "another thread of the visibility sort failed"
                );
                if spins < SPINS {
                    std::hint::spin_loop();
                    spins += 1;
                } else {
                    std::thread::yield_now();
                }
            }
        }
        sum.load(Ordering::Acquire)
    }
}

/// The threads' common state for one run of the levels.
struct Levels<'a, C> {
    team: Team<C>,
    nbs: &'a [[u32; 4]],
    chunking: Chunking,
}

impl<C: Carry> Levels<'_, C> {
    /// Thread `t`'s part from level `level` until a level is empty everywhere; `chunks` are its
    /// chunks `t`, `t + threads`, …. Returns the empty level.
    fn run(&self, t: usize, chunks: &mut [Chunk<'_, C>], mut level: u32) -> u32 {
        let threads = self.team.threads;
        let _bail = Bail(&self.team);
        // The team meets again after a cycle was broken: its meetings go on counting.
        let mut meeting = self.team.generation.load(Ordering::Acquire);
        loop {
            let parity = level as usize & 1;
            let mut work = 0;
            {
                let mut out: Vec<_> = (0..threads)
                    .map(|to| self.team.mail(parity, t, to))
                    .collect();
                for o in &mut out {
                    o.cells.clear();
                    o.carried.clear();
                    o.ends.clear();
                }
                for (i, chunk) in chunks.iter_mut().enumerate() {
                    work += self.place(t + i * threads, chunk, level, &mut out);
                }
            }
            let total = self.team.meet(meeting, work);
            meeting += 1;
            if total == 0 {
                return level;
            }
            self.deliver(t, chunks, parity);
            level += 1;
        }
    }

    /// Chunk `k`'s cells of `level`: each tells the cells in front of it, its own chunk's
    /// directly and the others' by mail. Returns how many cells it placed.
    fn place(
        &self,
        k: usize,
        chunk: &mut Chunk<'_, C>,
        level: u32,
        out: &mut [MutexGuard<Mail<C>>],
    ) -> usize {
        // Locals, so that the loop keeps them in registers.
        let (nbs, chunking, threads) = (self.nbs, self.chunking, out.len());
        let Chunk {
            state,
            carried,
            placed,
            begin,
            levels,
        } = chunk;
        let (begin, end) = (*begin, placed.len());
        for i in begin..end {
            // The neighbour table is the one array read out of order, and a level's cells are
            // known ahead: ask for their rows early.
            if i + AHEAD < end {
                crate::cache::prefetch(&nbs[placed[i + AHEAD] as usize]);
            }
            // What the cells carry is read out of order too: the cell's own a row ahead, and
            // the slots of its neighbours in front half a row ahead, once their numbers are in.
            if carries::<C>() {
                if i + AHEAD < end {
                    crate::cache::prefetch(&carried[chunking.within(placed[i + AHEAD])]);
                }
                if i + AHEAD / 2 < end {
                    let ahead = placed[i + AHEAD / 2];
                    let front = state[chunking.within(ahead)] & 0xF;
                    for f in 0..4 {
                        let m = nbs[ahead as usize][f];
                        if front & (1 << f) != 0 && chunking.of(m) == k {
                            crate::cache::prefetch(&carried[chunking.within(m)]);
                        }
                    }
                }
            }
            let c = placed[i];
            let front = state[chunking.within(c)] & 0xF;
            let told = carried_at(carried, chunking.within(c));
            for f in 0..4 {
                if front & (1 << f) != 0 {
                    let m = nbs[c as usize][f];
                    let km = chunking.of(m);
                    if km == k {
                        let j = chunking.within(m);
                        if carries::<C>() && state[j] & QUEUED == 0 {
                            carried[j].take(told);
                        }
                        if release(&mut state[j]) {
                            placed.push(m);
                        }
                    } else {
                        out[km % threads].cells.push(m);
                        if carries::<C>() {
                            out[km % threads].carried.push(told);
                        }
                    }
                }
            }
        }
        for o in out.iter_mut() {
            let len = o.cells.len();
            if o.ends.last().map_or(0, |e| e.1) < len {
                o.ends.push((k, len));
            }
        }
        chunk.begin = end;
        if end > begin {
            levels.push((level, (end - begin) as u32));
        }
        end - begin
    }

    /// The mail of this level for thread `t`, read in the order of the sending chunks.
    fn deliver(&self, t: usize, chunks: &mut [Chunk<'_, C>], parity: usize) {
        let threads = self.team.threads;
        let inbox: Vec<_> = (0..threads)
            .map(|from| self.team.mail(parity, from, t))
            .collect();
        let mut next = vec![(0usize, 0usize); threads];
        for k in 0..self.chunking.count {
            let from = k % threads;
            let (seg, start) = next[from];
            let Some(&(sender, end)) = inbox[from].ends.get(seg) else {
                continue;
            };
            if sender != k {
                continue;
            }
            for i in start..end {
                let m = inbox[from].cells[i];
                let chunk = &mut chunks[self.chunking.of(m) / threads];
                let j = self.chunking.within(m);
                if carries::<C>() && chunk.state[j] & QUEUED == 0 {
                    chunk.carried[j].take(inbox[from].carried[i]);
                }
                if release(&mut chunk.state[j]) {
                    chunk.placed.push(m);
                }
            }
            next[from] = (seg + 1, end);
        }
    }
}

/// A sort by levels: the cells level by level, where each level starts, and which levels hold
/// a cell forced out of a visibility cycle (alone).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Levelled {
    pub order: Vec<u32>,
    /// The start of each level in `order`, and its end last.
    pub starts: Vec<usize>,
    /// The levels that hold a forced cell, ascending.
    pub forced: Vec<u32>,
}

impl Levelled {
    pub fn into_order(self) -> Order {
        Order {
            back_to_front: self.order,
            cycle_cells: self.forced.len(),
        }
    }
}

/// Kahn's sort by levels over the relation `state` (one byte per cell: the faces with a cell in
/// front, the count of cells behind, whether queued), on `threads` threads (the order is the
/// same for any number). The faces' bits of `state` are left as they were.
///
/// Each placed cell tells the cells in front of it what it carries ([`Carry::take`]), and a
/// cell is placed once it has been told by all of them. Where a visibility cycle is broken, the
/// cells still waiting start afresh (`fresh`): what the cells placed before told them no longer
/// holds them back.
///
/// With `in_levels` false, where no cycle was broken, the order is left chunk by chunk instead
/// of level by level (for a caller that sorts the cells anew): it saves a copy of the order at
/// the sort's busiest moment.
pub(super) fn by_levels<C: Carry>(
    input: &SortInput,
    state: &mut [u8],
    carried: &mut [C],
    fresh: impl Fn(usize) -> C + Sync,
    threads: usize,
    in_levels: bool,
) -> Levelled {
    let n = input.mesh.tet_count();
    let chunking = Chunking::new(n);
    let mut buffer = vec![0u32; n];
    let mut chunks: Vec<Chunk<C>> = state
        .chunks_mut(1 << chunking.shift)
        .zip(carried.chunks_mut(1 << chunking.shift))
        .zip(buffer.chunks_mut(1 << chunking.shift))
        .map(|((state, carried), cells)| Chunk {
            placed: Placed { cells, len: 0 },
            state,
            carried,
            ..Chunk::default()
        })
        .collect();
    let threads = threads.clamp(1, chunks.len().max(1));
    for (k, chunk) in chunks.iter_mut().enumerate() {
        for (i, s) in chunk.state.iter_mut().enumerate() {
            if behind_count(*s) == 0 {
                *s |= QUEUED;
                chunk.placed.push(((k << chunking.shift) + i) as u32);
            }
        }
    }
    let run = Levels {
        team: Team::new(threads),
        nbs: input.mesh.neighbors(),
        chunking,
    };
    let mut level = 0;
    let mut forced = Vec::new();
    loop {
        level = run_team(&run, &mut chunks, level);
        let placed: usize = chunks.iter().map(|c| c.placed.len()).sum();
        if placed == n {
            break;
        }
        // A visibility cycle: the farthest cell still waiting goes next, alone in its level.
        let waiting =
            |c: usize| chunks[c >> chunking.shift].state[chunking.within(c as u32)] & QUEUED == 0;
        let Some(c) = farthest_waiting(input, waiting) else {
            break;
        };
        forced.push(level);
        if carries::<C>() {
            chunks.par_iter_mut().enumerate().for_each(|(k, chunk)| {
                let cells = chunk.state.iter().zip(chunk.carried.iter_mut());
                for (i, (s, carried)) in cells.enumerate() {
                    if s & QUEUED == 0 {
                        *carried = fresh((k << chunking.shift) + i);
                    }
                }
            });
        }
        let chunk = &mut chunks[chunking.of(c as u32)];
        chunk.state[chunking.within(c as u32)] |= QUEUED;
        chunk.placed.push(c as u32);
    }
    let starts = level_starts(&chunks);
    let order = if in_levels || !forced.is_empty() {
        in_level_order(&chunks, n)
    } else {
        drop(chunks);
        buffer
    };
    Levelled {
        order,
        starts,
        forced,
    }
}

/// Runs the levels on the team's threads, each with its own chunks, from `level`.
fn run_team<C: Carry>(run: &Levels<C>, chunks: &mut [Chunk<'_, C>], level: u32) -> u32 {
    let threads = run.team.threads;
    // Thread t's chunks are t, t + threads, …: taken out, and put back afterwards.
    let mut mine: Vec<Vec<Chunk<C>>> = (0..threads).map(|_| Vec::new()).collect();
    for (k, c) in chunks.iter_mut().enumerate() {
        mine[k % threads].push(std::mem::take(c));
    }
    let mut rest = mine.split_off(1);
    let mut first = mine.pop().expect("one thread");
    let end = std::thread::scope(|s| {
        for (t, own) in rest.iter_mut().enumerate() {
            s.spawn(move || run.run(t + 1, own, level));
        }
        run.run(0, &mut first, level)
    });
    rest.insert(0, first);
    for (t, own) in rest.into_iter().enumerate() {
        for (i, c) in own.into_iter().enumerate() {
            chunks[t + i * threads] = c;
        }
    }
    end
}

/// The number of levels the chunks placed cells in.
fn level_count<C>(chunks: &[Chunk<'_, C>]) -> usize {
    chunks
        .iter()
        .filter_map(|c| c.levels.last())
        .map(|l| l.0 as usize + 1)
        .max()
        .unwrap_or(0)
}

/// Where each level starts in the order level by level, and its end last.
fn level_starts<C>(chunks: &[Chunk<'_, C>]) -> Vec<usize> {
    let mut sizes = vec![0usize; level_count(chunks) + 1];
    for chunk in chunks {
        for &(level, count) in &chunk.levels {
            sizes[level as usize + 1] += count as usize;
        }
    }
    for l in 1..sizes.len() {
        sizes[l] += sizes[l - 1];
    }
    sizes
}

/// All placed cells, level by level, and in a level chunk by chunk.
fn in_level_order<C>(chunks: &[Chunk<'_, C>], n: usize) -> Vec<u32> {
    let mut order = Vec::with_capacity(n);
    let mut next = vec![(0usize, 0usize); chunks.len()];
    for level in 0..level_count(chunks) {
        for (chunk, (seg, start)) in chunks.iter().zip(next.iter_mut()) {
            if let Some(&(l, count)) = chunk.levels.get(*seg)
                && l == level as u32
            {
                let end = *start + count as usize;
                order.extend_from_slice(&chunk.placed.cells[*start..end]);
                *seg += 1;
                *start = end;
            }
        }
    }
    order
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::mesh::generate::{SplitMix64, kuhn_box};
    use crate::mesh::{NO_NEIGHBOR, TetMesh};
    use crate::sort::mpvo::relation;
    use crate::sort::mpvo::tests::views;

    /// The serial first-in-first-out Kahn sort, cycles broken as in [`by_levels`]; returns the
    /// order and each cell's generation in the queue (cells queued while the previous
    /// generation was taken out, or a cell forced out of a cycle, alone).
    fn serial_fifo(input: &SortInput, mut state: Vec<u8>) -> (Vec<u32>, Vec<u32>, usize) {
        let n = input.mesh.tet_count();
        let nbs = input.mesh.neighbors();
        let mut queue: Vec<u32> = Vec::new();
        let mut generation = vec![u32::MAX; n];
        for c in 0..n {
            if behind_count(state[c]) == 0 {
                state[c] |= QUEUED;
                queue.push(c as u32);
                generation[c] = 0;
            }
        }
        let (mut next, mut cycles) = (0, 0);
        loop {
            while next < queue.len() {
                let c = queue[next] as usize;
                next += 1;
                for f in 0..4 {
                    if state[c] & (1 << f) != 0 {
                        let m = nbs[c][f] as usize;
                        if release(&mut state[m]) {
                            queue.push(m as u32);
                            generation[m] = generation[c] + 1;
                        }
                    }
                }
            }
            if queue.len() == n {
                break;
            }
            let last = generation[*queue.last().unwrap() as usize];
            let c = farthest_waiting(input, |c| state[c] & QUEUED == 0).unwrap();
            state[c] |= QUEUED;
            queue.push(c as u32);
            generation[c] = last + 1;
            cycles += 1;
        }
        (queue, generation, cycles)
    }

    /// Sorted by levels on 1, 2, 3 and 5 threads: the same order every time, holding every
    /// cell once, with the serial sort's generations in the same sequence (the same cells in
    /// each level) and as many cells forced out of cycles.
    fn check(input: &SortInput, state: Vec<u8>) -> usize {
        let (_, generation, cycles) = serial_fifo(input, state.clone());
        let one = by_levels(
            input,
            &mut state.clone(),
            &mut vec![(); state.len()],
            |_| (),
            1,
            true,
        );
        for threads in [2, 3, 5] {
            assert_eq!(
                by_levels(
                    input,
                    &mut state.clone(),
                    &mut vec![(); state.len()],
                    |_| (),
                    threads,
                    true,
                ),
                one,
                "{threads} threads"
            );
        }
        assert_eq!(one.forced.len(), cycles);
        // Left chunk by chunk: the same cells and levels (level by level where cycles split it).
        let loose = by_levels(
            input,
            &mut state.clone(),
            &mut vec![(); state.len()],
            |_| (),
            2,
            false,
        );
        assert_eq!((&loose.starts, &loose.forced), (&one.starts, &one.forced));
        let mut cells = loose.order.clone();
        cells.sort_unstable();
        assert!(cells.iter().enumerate().all(|(i, &c)| c as usize == i));
        assert_eq!(cycles > 0, loose.order == one.order);
        assert_eq!(
            one.starts.len() as u32,
            generation.iter().max().unwrap() + 2
        );
        for w in one.starts.windows(2) {
            let g = generation[one.order[w[0]] as usize];
            assert!(
                one.order[w[0]..w[1]]
                    .iter()
                    .all(|&c| generation[c as usize] == g)
            );
        }
        let mut seen = vec![false; input.mesh.tet_count()];
        let mut by_gen: Vec<u32> = one
            .order
            .iter()
            .map(|&c| {
                assert!(
                    !std::mem::replace(&mut seen[c as usize], true),
                    "cell {c} twice"
                );
                generation[c as usize]
            })
            .collect();
        assert!(seen.iter().all(|&s| s), "every cell placed");
        assert!(by_gen.is_sorted(), "the order goes level by level");
        by_gen.dedup();
        assert_eq!(by_gen.len() as u32, generation.iter().max().unwrap() + 1);
        cycles
    }

    #[test]
    fn levels_are_the_serial_sorts_on_any_number_of_threads() {
        let (nodes, tets) = kuhn_box([14, 11, 9], [1.0; 3], 0.15, 3);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        assert!(Chunking::new(mesh.tet_count()).count > 30, "many chunks");
        for (eye, screen, perspective) in views(&mesh, 11, 6, 3.0) {
            let input = SortInput {
                mesh: &mesh,
                eye_nodes: &eye,
                screen: &screen,
                perspective,
                mirrored: false,
            };
            assert_eq!(check(&input, relation(&input)), 0);
            let order = by_levels(
                &input,
                &mut relation(&input),
                &mut vec![(); mesh.tet_count()],
                |_| (),
                3,
                true,
            );
            crate::sort::mpvo::tests::assert_valid(&input, &order.order);
        }
    }

    /// Faces turned at random: the relation is full of cycles, broken one cell at a time.
    #[test]
    fn cycles_are_broken_as_the_serial_sort_breaks_them() {
        let (mesh, eye, screen) = turned_box();
        let input = SortInput {
            mesh: &mesh,
            eye_nodes: &eye,
            screen: &screen,
            perspective: false,
            mirrored: false,
        };
        let state = random_relation(&mesh, 8);
        assert!(check(&input, state) > 10, "cycles were broken");
    }

    /// A small jittered box turned at random, seen orthographically: the scene of the tests
    /// with relations turned at random.
    pub(crate) fn turned_box() -> (TetMesh, Vec<[f64; 3]>, Vec<[f64; 2]>) {
        let (nodes, tets) = kuhn_box([9, 8, 7], [1.0; 3], 0.1, 5);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        let (eye, screen, _) = views(&mesh, 2, 2, 3.0).nth(1).unwrap();
        (mesh, eye, screen)
    }

    /// A relation with every face turned at random (one in ten left undecided): full of cycles.
    pub(crate) fn random_relation(mesh: &TetMesh, seed: u64) -> Vec<u8> {
        let mut rng = SplitMix64(seed);
        let mut state = vec![0u8; mesh.tet_count()];
        for c in 0..mesh.tet_count() {
            for f in 0..4 {
                let m = mesh.neighbors()[c][f];
                // Each face once, from its lower-numbered cell; one in ten left undecided.
                if m == NO_NEIGHBOR || (m as usize) < c {
                    continue;
                }
                let x = rng.next_f64();
                let g = (0..4)
                    .find(|&g| mesh.neighbors()[m as usize][g] == c as u32)
                    .unwrap();
                let (front, behind) = match x {
                    x if x < 0.45 => ((c, f), m as usize),
                    x if x < 0.9 => ((m as usize, g), c),
                    _ => continue,
                };
                state[front.0] |= 1 << front.1;
                state[behind] += 1 << 4;
            }
        }
        state
    }
}
