//! The A* open list (`docs/algorithms.md` §5): keys packed so that the least pops first, a ring
//! of buckets over `f` whose current bucket is an exact 4-ary heap, and lazy deletion.
//!
//! Keys order by `f`, then the larger `g` (compared to 25 mantissa bits), then the smaller cell
//! index, so a search popping from this list is a pure function of its inputs. A popped entry
//! whose cell is already closed is skipped by the search, and the entries of closed cells are
//! dropped when their bucket is taken into the heap (most stale entries never reach the heap).

/// Bits of a cell index in an open-list key ([`crate::map::grid::MAX_CELLS`] < 2^27).
pub(super) const IDX_BITS: u32 = 27;

/// An open-list entry packed into one `u128` so that the smallest key pops first:
/// - bits 127..64: `f` as the bit pattern of a non-negative finite `f64` (ordered like `f`);
/// - bits 63..27: the complement of the top 37 bits of `g` (sign, exponent and 25 mantissa bits),
///   so that among equal `f` the larger `g` pops first (`g` compared to ~3e-8 relative precision);
/// - bits 26..0: the cell index, so remaining ties go to the smaller index.
pub(super) type Open = u128;

#[inline]
pub(super) fn open_entry(f: f64, g: f64, idx: u32) -> Open {
    let g_key = (!g.to_bits()) >> IDX_BITS;
    (u128::from(f.to_bits()) << 64) | (u128::from(g_key) << IDX_BITS) | u128::from(idx)
}

/// The cell index stored in an open-list key.
#[inline]
pub(super) fn open_index(e: Open) -> usize {
    (e as u64 & ((1u64 << IDX_BITS) - 1)) as usize
}

/// Buckets in the open list's ring (a power of two).
pub(super) const RING: usize = 1024;
/// Entries a bucket's buffer may keep between searches (16 bytes each).
pub(super) const BUCKET_KEEP: usize = 64;
/// Buckets spanned by the largest possible step in `f` between a popped entry and one it pushes;
/// half the ring, so rounding can never wrap an entry onto a bucket still in use.
pub(super) const REACH: f64 = 512.0;

/// The open list: a ring of [`RING`] buckets on `f` with an exact 4-ary min-heap for the current
/// bucket.
///
/// The bucket width is `max_step / REACH`, with `max_step` a bound on how much `f` can grow from
/// a popped entry to an entry it pushes (the largest move cost plus the largest change of the
/// heuristic over one move), so every pending entry lies less than `REACH + 2` buckets ahead of
/// the current one and the ring never wraps onto itself: its few buckets stay in cache, and a
/// push beyond the current bucket is an O(1) append. When the heap runs dry the next non-empty
/// bucket is heapified. With a consistent heuristic the popped `f` never decreases, and an entry
/// that lands in (or, by rounding, below) the current bucket goes straight into the heap, so pops
/// come out in exactly the order of the keys — the same order as one global heap.
#[derive(Debug)]
pub(super) struct OpenList {
    heap: Vec<Open>,
    pub(super) buckets: Vec<Vec<Open>>,
    /// Current bucket number (not reduced modulo the ring).
    cur: usize,
    /// Entries waiting in future buckets.
    pending: usize,
    /// 1 / bucket width (per metre).
    inv_width: f64,
    /// Farthest any push landed ahead of the current bucket since the last reset (tests check it
    /// stays below `REACH + 2`).
    #[cfg(test)]
    pub(super) max_ahead: usize,
}

impl Default for OpenList {
    fn default() -> Self {
        Self {
            heap: Vec::new(),
            buckets: vec![Vec::new(); RING],
            cur: 0,
            pending: 0,
            inv_width: 1.0,
            #[cfg(test)]
            max_ahead: 0,
        }
    }
}

impl OpenList {
    /// Empties the list for a search whose `f` grows by at most `max_step` (metres, finite and
    /// `> 0`) per push and whose first entry has key `f0`.
    pub(super) fn reset(&mut self, max_step: f64, f0: f64) {
        self.heap.clear();
        for b in &mut self.buckets {
            // A bucket keeps a small buffer across searches; a large one is released, or over
            // many searches every bucket of the ring would come to hold the largest load any
            // bucket ever had (the process grew by about 90 MB over 6000 museum plans).
            if b.capacity() > BUCKET_KEEP {
                *b = Vec::new();
            } else {
                b.clear();
            }
        }
        self.pending = 0;
        self.inv_width = REACH / max_step;
        self.cur = self.bucket(f0);
        #[cfg(test)]
        {
            self.max_ahead = 0;
        }
    }

    /// The bucket number of `f` (finite and `>= 0`; the float-to-int cast saturates, and is to
    /// `i64`, which x86-64 converts to in one instruction: a bucket number stays far below 2^63).
    #[inline]
    fn bucket(&self, f: f64) -> usize {
        (f * self.inv_width) as i64 as usize
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: Open, f: f64) {
        let b = self.bucket(f);
        if b <= self.cur {
            self.heap_push(e);
        } else {
            debug_assert!(b - self.cur < RING, "f step beyond the ring: {} buckets", b - self.cur);
            #[cfg(test)]
            {
                self.max_ahead = self.max_ahead.max(b - self.cur);
            }
            self.buckets[b % RING].push(e);
            self.pending += 1;
        }
    }

    /// Pops the least entry. When the heap runs dry and the next bucket is taken in, its entries
    /// whose cell is `closed` are dropped (stale: popped, they would be skipped), which leaves the
    /// sequence of entries that are not skipped unchanged.
    #[inline]
    pub(super) fn pop(&mut self, closed: impl Fn(usize) -> bool) -> Option<Open> {
        loop {
            if let Some(e) = self.heap_pop() {
                return Some(e);
            }
            if self.pending == 0 {
                return None;
            }
            // Advance to the next non-empty bucket (one exists within the ring) and heapify it
            // (the heap is empty).
            self.cur += 1;
            while self.buckets[self.cur % RING].is_empty() {
                self.cur += 1;
            }
            // Copied, not swapped: a swap moved the heap's grown buffer into a bucket at every
            // refill, so over many searches each of the RING buckets came to hold a buffer as
            // large as the biggest heap (about 90 MB after 6000 museum plans, growing on). Each
            // buffer now stays with its own Vec, bounded by the most that Vec ever held.
            let bucket = &mut self.buckets[self.cur % RING];
            self.pending -= bucket.len();
            self.heap.extend(bucket.iter().filter(|&&e| !closed(open_index(e))));
            bucket.clear();
            let n = self.heap.len();
            for i in (0..n.div_ceil(4)).rev() {
                let e = self.heap[i];
                self.sift_down(i, e);
            }
        }
    }

    #[inline]
    fn heap_push(&mut self, e: Open) {
        let mut i = self.heap.len();
        self.heap.push(e);
        while i > 0 {
            let p = (i - 1) / 4;
            if e < self.heap[p] {
                self.heap[i] = self.heap[p];
                i = p;
            } else {
                break;
            }
        }
        self.heap[i] = e;
    }

    #[inline]
    fn heap_pop(&mut self) -> Option<Open> {
        let last = self.heap.pop()?;
        if self.heap.is_empty() {
            return Some(last);
        }
        let top = self.heap[0];
        self.sift_down(0, last);
        Some(top)
    }

    /// Places `e` at slot `i` and sifts it down.
    #[inline]
    fn sift_down(&mut self, mut i: usize, e: Open) {
        let n = self.heap.len();
        loop {
            let c = 4 * i + 1;
            if c >= n {
                break;
            }
            let (mut m, mut best) = (c, self.heap[c]);
            if let Some(&[x1, x2, x3]) = self.heap.get(c + 1..c + 4) {
                // All four children (the common case): the least of two pairs' least.
                let (m1, b1) = if x1 < best { (c + 1, x1) } else { (c, best) };
                let (m2, b2) = if x3 < x2 { (c + 3, x3) } else { (c + 2, x2) };
                (m, best) = if b2 < b1 { (m2, b2) } else { (m1, b1) };
            } else {
                for j in c + 1..n {
                    let x = self.heap[j];
                    if x < best {
                        best = x;
                        m = j;
                    }
                }
            }
            if best < e {
                self.heap[i] = best;
                i = m;
            } else {
                break;
            }
        }
        self.heap[i] = e;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_list_pops_in_key_order() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut ol = OpenList::default();
        for round in 0..3 {
            ol.reset(3.0, 0.0);
            let mut all = Vec::new();
            let mut floor = 0.0f64;
            // Interleave pushes (never below the last popped f, except by a rounding-sized amount)
            // and pops, like a search does.
            let mut popped = Vec::new();
            for step in 0..2000 {
                if step % 3 != 2 {
                    let f = floor + rng.random_range(0.0..3.0) - 1e-12;
                    let f = f.max(0.0);
                    let g = rng.random_range(0.0..f.max(1e-3));
                    let e = open_entry(f, g, rng.random_range(0..1000));
                    all.push(e);
                    ol.push(e, f);
                } else if let Some(e) = ol.pop(|_| false) {
                    floor = f64::from_bits((e >> 64) as u64);
                    popped.push(e);
                }
            }
            while let Some(e) = ol.pop(|_| false) {
                popped.push(e);
            }
            assert_eq!(popped.len(), all.len(), "round {round}");
            // Every pop was the minimum of what was in the queue at the time: popped keys ascend
            // except where a smaller key was pushed after a larger one was popped (the -1e-12).
            for w in popped.windows(2) {
                let (a, b) = (f64::from_bits((w[0] >> 64) as u64), f64::from_bits((w[1] >> 64) as u64));
                assert!(b >= a - 1e-9, "{a} then {b}");
            }
        }
        // Pure ordering: push everything first (all within one step of f = 0), pop all: exactly
        // sorted.
        ol.reset(11.0, 0.0);
        let mut keys: Vec<Open> = (0..500u32)
            .map(|i| {
                let f = f64::from(i % 37) * 0.3;
                let g = f64::from(i % 7) * 0.01;
                open_entry(f, g, i)
            })
            .collect();
        for &k in &keys {
            ol.push(k, f64::from_bits((k >> 64) as u64));
        }
        keys.sort_unstable();
        let out: Vec<Open> = std::iter::from_fn(|| ol.pop(|_| false)).collect();
        assert_eq!(out, keys);
        // Larger g first among equal f, then smaller index.
        assert!(open_entry(1.0, 0.6, 9) < open_entry(1.0, 0.5, 1));
        assert!(open_entry(1.0, 0.5, 1) < open_entry(1.0, 0.5, 2));
        assert!(open_entry(0.9, 0.0, 9) < open_entry(1.0, 0.9, 0));
    }
}
