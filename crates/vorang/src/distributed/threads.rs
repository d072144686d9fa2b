//! Ranks as threads of one process ("virtual ranks"): a [`Comm`] whose messages are vectors
//! handed over in memory, so that a distributed frame runs its very steps without MPI — in the
//! tests, and in `vorang --virtual-ranks N`, which renders what `mpirun -np N` renders.

use std::sync::{Arc, Barrier, Mutex};

use super::{Comm, Received};

/// One rank of a group of threads; [`Threads::group`] makes them.
pub struct Threads {
    rank: usize,
    shared: Arc<Shared>,
}

struct Shared {
    size: usize,
    barrier: Barrier,
    /// `mail[to][from]`: what rank `from` sends to rank `to` in the current exchange.
    mail: Mutex<Vec<Vec<Vec<u8>>>>,
}

impl Threads {
    /// `size` ranks that talk to each other; each is to be used by its own thread.
    pub fn group(size: usize) -> Vec<Threads> {
        let shared = Arc::new(Shared {
            size,
            barrier: Barrier::new(size),
            mail: Mutex::new(vec![vec![Vec::new(); size]; size]),
        });
        (0..size)
            .map(|rank| Threads {
                rank,
                shared: Arc::clone(&shared),
            })
            .collect()
    }

    /// Every rank hands `send[d]` to rank `d` and gets what every rank handed to it.
    fn exchange(&self, send: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        let s = &self.shared;
        {
            let mut mail = s.mail.lock().unwrap_or_else(|e| e.into_inner());
            for (to, bytes) in send.into_iter().enumerate() {
                mail[to][self.rank] = bytes;
            }
        }
        s.barrier.wait();
        let got = {
            let mut mail = s.mail.lock().unwrap_or_else(|e| e.into_inner());
            std::mem::replace(&mut mail[self.rank], vec![Vec::new(); s.size])
        };
        // Nobody posts the next exchange before everyone has taken this one's.
        s.barrier.wait();
        got
    }

    /// The same bytes to every rank; what every rank sent, by rank.
    fn all_gather(&self, bytes: Vec<u8>) -> Vec<Vec<u8>> {
        self.exchange(vec![bytes; self.shared.size])
    }
}

impl Comm for Threads {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn agree(&self, outcome: Result<(), String>) -> Result<(), String> {
        let mine = match outcome {
            Ok(()) => Vec::new(),
            Err(m) => {
                let mut b = vec![1];
                b.extend_from_slice(m.as_bytes());
                b
            }
        };
        match self.all_gather(mine).into_iter().find(|b| !b.is_empty()) {
            None => Ok(()),
            Some(b) => Err(String::from_utf8_lossy(&b[1..]).into_owned()),
        }
    }

    fn min_f64(&self, values: &mut [f64]) {
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        for other in self.all_gather(bytes) {
            for (v, c) in values.iter_mut().zip(other.chunks_exact(8)) {
                let o = f64::from_le_bytes(c.try_into().unwrap_or([0; 8]));
                if o < *v {
                    *v = o;
                }
            }
        }
    }

    fn sum_u64(&self, values: &mut [u64]) {
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        values.fill(0);
        for other in self.all_gather(bytes) {
            for (v, c) in values.iter_mut().zip(other.chunks_exact(8)) {
                *v += u64::from_le_bytes(c.try_into().unwrap_or([0; 8]));
            }
        }
    }

    fn all_to_all(&self, send: Vec<Vec<u8>>) -> Received {
        Received::concat(self.exchange(send))
    }

    fn gather(&self, mine: Vec<u8>) -> Option<Vec<Vec<u8>>> {
        let mut send = vec![Vec::new(); self.shared.size];
        send[0] = mine;
        let got = self.exchange(send);
        (self.rank == 0).then_some(got)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threads_agree_reduce_and_exchange() {
        let ranks = Threads::group(3);
        std::thread::scope(|s| {
            for comm in &ranks {
                s.spawn(move || {
                    let r = comm.rank();
                    let fail = if r >= 1 {
                        Err(format!("rank {r} failed"))
                    } else {
                        Ok(())
                    };
                    assert_eq!(comm.agree(fail), Err("rank 1 failed".into()));
                    assert_eq!(comm.agree(Ok(())), Ok(()));
                    let mut v = [r as f64, 10.0 - r as f64];
                    comm.min_f64(&mut v);
                    assert_eq!(v, [0.0, 8.0]);
                    let mut n = [r as u64 + 1];
                    comm.sum_u64(&mut n);
                    assert_eq!(n, [6]);
                    let got = comm.all_to_all((0..3).map(|d| vec![r as u8, d as u8]).collect());
                    let want: Vec<Vec<u8>> = (0..3).map(|s| vec![s as u8, r as u8]).collect();
                    assert_eq!(
                        got.parts(),
                        want.iter().map(Vec::as_slice).collect::<Vec<_>>()
                    );
                    let g = comm.gather(vec![r as u8; r]);
                    if r == 0 {
                        assert_eq!(g, Some(vec![vec![], vec![1], vec![2, 2]]));
                    } else {
                        assert_eq!(g, None);
                    }
                });
            }
        });
    }
}
