//! An answer kept with the bits of the inputs it was computed from, for the shadow-map host
//! work that would otherwise repeat every frame (`samples.rs`, `fits.rs`). The inputs are
//! compared exactly as bits (a `-0.0` for a `0.0`, or a NaN, computes again): asked with the
//! same bits, the kept answer is the one computing would give.

/// One computation's last key (its inputs' bits) and answer.
pub(crate) struct Kept<T> {
    key: Vec<u32>,
    answer: T,
}

impl<T: Clone> Kept<T> {
    /// The answer for the inputs whose bits `current` holds: the kept one when they are the
    /// same, otherwise `compute()`, kept with them. `current` is scratch storage, swapped with
    /// the kept key on a miss (no allocation once warm).
    pub fn answer(slot: &mut Option<Self>, current: &mut Vec<u32>, compute: impl FnOnce() -> T) -> T {
        match slot {
            Some(kept) if kept.key == *current => kept.answer.clone(),
            Some(kept) => {
                kept.answer = compute();
                std::mem::swap(&mut kept.key, current);
                kept.answer.clone()
            }
            None => {
                let answer = compute();
                slot.insert(Kept { key: std::mem::take(current), answer }).answer.clone()
            }
        }
    }
}
