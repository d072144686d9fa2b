//! How many render threads a rank runs: the ranks on one node divide its cores.
//!
//! Left alone, rayon starts one thread per CPU a process may run on. Ranks that share a node
//! and are not bound to cores of their own (`--bind-to none`) would then each start a thread
//! per core — N ranks, N threads on every core — and the renderer's threads, which meet at every
//! level of the visibility sort, would spend their time waiting for each other's turn on a
//! core. So each rank counts, for every CPU it may run on, how many ranks of its node may run on
//! it too, and takes its part: ranks that share all of a node's cores get an equal part each,
//! ranks bound to cores of their own keep them. `RAYON_NUM_THREADS` still decides where it is
//! set.

use std::collections::BTreeMap;

use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// A set of CPUs: CPU `c` is bit `c % 64` of word `c / 64`.
pub type Cpus = Vec<u64>;

fn has(cpus: &[u64], c: usize) -> bool {
    cpus.get(c / 64).is_some_and(|w| (w >> (c % 64)) & 1 == 1)
}

/// The CPUs `0 .. n`.
pub fn first(n: usize) -> Cpus {
    let mut cpus = vec![0u64; n.div_ceil(64).max(1)];
    for c in 0..n {
        cpus[c / 64] |= 1 << (c % 64);
    }
    cpus
}

/// The threads of each rank of a node, given the CPUs each may run on (`masks[r]`, by local
/// rank).
///
/// A rank's share is the sum over its CPUs of one over the number of ranks that may run on
/// that CPU; counted in whole threads so that the node's CPUs are all handed out and none
/// twice. The CPUs that the same ranks may run on form one class, divided evenly among those
/// ranks; what does not divide evenly goes one CPU each to the class's ranks with the fewest
/// threads so far, the lower local rank first (ranks do alike work, so the one with the fewest
/// threads would hold up the others). Where each rank's CPUs are one class — ranks unbound, or
/// bound per core or per socket — that is its share rounded down or up (3 ranks sharing 16
/// CPUs: 6, 5 and 5). A rank gets at least one thread, even where that oversubscribes (more
/// ranks than CPUs).
pub fn shares(masks: &[Cpus]) -> Vec<usize> {
    let ranks = masks.len();
    let cpus = masks.iter().map(|m| m.len() * 64).max().unwrap_or(0);
    // Each CPU's ranks (a bit set of local ranks), and how many CPUs have the same ones.
    let mut classes: BTreeMap<Vec<u64>, usize> = BTreeMap::new();
    for c in 0..cpus {
        let mut set = vec![0u64; ranks.div_ceil(64)];
        for (r, mask) in masks.iter().enumerate() {
            if has(mask, c) {
                set[r / 64] |= 1 << (r % 64);
            }
        }
        if set.iter().any(|&w| w != 0) {
            *classes.entry(set).or_default() += 1;
        }
    }
    let mut threads = vec![0usize; ranks];
    let mut left = Vec::new();
    for (set, &n) in &classes {
        let members: Vec<usize> = (0..ranks).filter(|&r| has(set, r)).collect();
        let k = members.len();
        for &r in &members {
            threads[r] += n / k;
        }
        if n % k > 0 {
            left.push((members, n % k));
        }
    }
    // The remainders after every class's even part, so that "fewest so far" counts them all.
    for (mut members, extra) in left {
        for _ in 0..extra {
            let (i, _) = members
                .iter()
                .enumerate()
                .min_by_key(|&(_, &r)| (threads[r], r))
                .expect("fewer CPUs left over than ranks in the class");
            threads[members.swap_remove(i)] += 1;
        }
    }
    threads.into_iter().map(|t| t.max(1)).collect()
}

/// Local rank `rank`'s threads among ranks that may run on `masks`: its [`shares`] part, and
/// never more than rayon would start by itself (`available_parallelism`, which also counts a
/// cgroup's CPU quota).
pub fn threads(masks: &[Cpus], rank: usize) -> usize {
    let alone = std::thread::available_parallelism().map_or(1, |n| n.get());
    shares(masks).get(rank).map_or(1, |&t| t.min(alone))
}

/// The CPUs this thread may run on: its affinity mask where the system tells it, else the CPUs
/// `0 .. available_parallelism`.
pub fn affinity() -> Cpus {
    #[cfg(target_os = "linux")]
    if let Some(cpus) = linux_affinity() {
        return cpus;
    }
    first(std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// `sched_getaffinity` of this thread, with a mask as large as the kernel's (it refuses one
/// smaller than its own with `EINVAL`).
#[cfg(target_os = "linux")]
fn linux_affinity() -> Option<Cpus> {
    const BITS: usize = libc::c_ulong::BITS as usize;
    let mut bits = 1024;
    while bits <= 1 << 20 {
        let mut words: Vec<libc::c_ulong> = vec![0; bits / BITS];
        // SAFETY: the kernel (and glibc's wrapper) writes at most `size_of_val(&words[..])`
        // bytes at the pointer, which `words` owns; the mask is an array of `unsigned long`
        // (as `cpu_set_t` is), so the pointer is aligned for it. Pid 0 is this thread.
        let got = unsafe {
            libc::sched_getaffinity(
                0,
                std::mem::size_of_val(&words[..]),
                words.as_mut_ptr().cast::<libc::cpu_set_t>(),
            )
        };
        if got == 0 {
            let mut cpus = vec![0u64; bits.div_ceil(64)];
            for c in 0..bits {
                if (words[c / BITS] >> (c % BITS)) & 1 == 1 {
                    cpus[c / 64] |= 1 << (c % 64);
                }
            }
            return cpus.iter().any(|&w| w != 0).then_some(cpus);
        }
        if std::io::Error::last_os_error().raw_os_error() != Some(libc::EINVAL) {
            return None;
        }
        bits *= 2;
    }
    None
}

/// Sizes rayon's global pool to this rank's part of its node's cores ([`shares`]), unless
/// `RAYON_NUM_THREADS` sets it. Collective over `world`: every rank calls it, before any
/// rayon work (a pool that already exists stays as it is).
pub(crate) fn divide(world: &SimpleCommunicator) {
    let node = world.split_shared(world.rank());
    let mine = affinity();
    // Every rank's mask as long as the longest.
    let mut words = 0u64;
    node.all_reduce_into(&(mine.len() as u64), &mut words, SystemOperation::max());
    let words = words as usize;
    let mut padded = mine;
    padded.resize(words, 0);
    let mut all = vec![0u64; words * node.size() as usize];
    node.all_gather_into(&padded[..], &mut all[..]);
    let masks: Vec<Cpus> = all.chunks(words).map(<[u64]>::to_vec).collect();
    let threads = threads(&masks, node.rank() as usize);
    // The user's word wins (rayon's own variables, the old name too).
    let set = ["RAYON_NUM_THREADS", "RAYON_RS_NUM_CPUS"]
        .iter()
        .any(|v| std::env::var_os(v).is_some());
    if !set {
        // Fails only if the pool exists already: then it keeps its size.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CPUs `from .. to`.
    fn range(from: usize, to: usize) -> Cpus {
        let mut cpus = first(to);
        for c in 0..from {
            cpus[c / 64] &= !(1 << (c % 64));
        }
        cpus
    }

    #[test]
    fn unbound_ranks_share_the_node_evenly() {
        assert_eq!(shares(&vec![first(16); 4]), [4, 4, 4, 4]);
        assert_eq!(shares(&vec![first(16); 1]), [16]);
        assert_eq!(shares(&vec![first(128); 2]), [64, 64]);
    }

    #[test]
    fn ranks_bound_to_a_core_each_keep_it() {
        let masks: Vec<Cpus> = (0..16).map(|c| range(c, c + 1)).collect();
        assert_eq!(shares(&masks), vec![1; 16]);
        // Eight ranks bound to cores 8 .. 15 of 16.
        let masks: Vec<Cpus> = (8..16).map(|c| range(c, c + 1)).collect();
        assert_eq!(shares(&masks), vec![1; 8]);
    }

    #[test]
    fn ranks_bound_to_a_socket_share_it() {
        // Two sockets of 8 cores, two ranks on each (Open MPI's --bind-to socket).
        let (a, b) = (range(0, 8), range(8, 16));
        assert_eq!(shares(&[a.clone(), b.clone(), a, b]), [4, 4, 4, 4]);
        // Two sockets of 32 cores with hyperthreads (CPU c and c + 64 on one core).
        let socket = |s: usize| {
            let mut cpus = range(32 * s, 32 * s + 32);
            cpus.resize(2, 0);
            cpus[1] = cpus[0];
            cpus
        };
        assert_eq!(
            shares(&[socket(0), socket(0), socket(1), socket(1)]),
            [32, 32, 32, 32]
        );
    }

    #[test]
    fn uneven_parts_hand_out_every_cpu_once() {
        // Lower local ranks take the CPUs left over.
        assert_eq!(shares(&vec![first(16); 3]), [6, 5, 5]);
        assert_eq!(shares(&vec![first(16); 5]), [4, 3, 3, 3, 3]);
        assert_eq!(shares(&vec![first(16); 6]), [3, 3, 3, 3, 2, 2]);
        assert_eq!(shares(&vec![first(2); 2]), [1, 1]);
        for cpus in 1..=40 {
            for ranks in 1..=cpus {
                let s = shares(&vec![first(cpus); ranks]);
                assert_eq!(s.iter().sum::<usize>(), cpus, "{ranks} ranks on {cpus}");
                assert!(s.iter().all(|&t| t >= 1 && t <= cpus.div_ceil(ranks)));
                assert!(s.windows(2).all(|w| w[0] >= w[1]));
            }
        }
    }

    #[test]
    fn more_ranks_than_cpus_run_one_thread_each() {
        assert_eq!(shares(&vec![first(2); 3]), [1, 1, 1]);
        assert_eq!(shares(&vec![first(1); 4]), [1, 1, 1, 1]);
        assert_eq!(shares(&[first(0)]), [1]);
        assert_eq!(shares(&[]), Vec::<usize>::new());
    }

    #[test]
    fn overlapping_masks_count_each_cpu_by_its_ranks() {
        // One rank on all 16 CPUs, one on the first 8: the 8 shared CPUs are split.
        assert_eq!(shares(&[first(16), first(8)]), [12, 4]);
        assert_eq!(shares(&[range(8, 16), first(16)]), [4, 12]);
        // Two ranks on a socket, one unbound: 3 ranks share 0 .. 7, one rank has 8 .. 15.
        let s = shares(&[range(0, 8), range(0, 8), first(16)]);
        assert_eq!(s.iter().sum::<usize>(), 16);
        assert_eq!(s, [3, 3, 10]);
        // Leftovers of several classes go to the ranks with the fewest threads, not all to
        // the lowest rank: one rank on 6 CPUs, two bound to 3 of them each.
        assert_eq!(shares(&[first(6), first(3), range(3, 6)]), [2, 2, 2]);
    }

    #[test]
    fn a_rank_takes_no_more_threads_than_rayon_would() {
        let alone = std::thread::available_parallelism().map_or(1, |n| n.get());
        assert!(threads(&[first(4096)], 0) <= alone);
        assert_eq!(threads(&[first(1)], 0), 1);
    }

    #[test]
    fn this_process_may_run_on_some_cpu() {
        let mine = affinity();
        let n: u32 = mine.iter().map(|w| w.count_ones()).sum();
        assert!(n >= 1);
        #[cfg(target_os = "linux")]
        assert!(
            n as usize >= std::thread::available_parallelism().map_or(1, |n| n.get()),
            "the mask counts at least the CPUs rayon would use"
        );
    }
}
