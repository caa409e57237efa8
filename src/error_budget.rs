//! An error budget (`render --error RMSE`): a render that sums into a film
//! in batches (forward, or ray tracing with bounces) stops once its own
//! estimate of its error is within the budget, with no reference image.
//!
//! The work is dealt into two halves, each an independent estimate of the
//! image: the forward tracer's batches of photons alternately (every photon
//! is drawn from its own hash), and the ray tracer's even and odd samples of
//! every pixel (two streams of the progressive sequence, scrambled apart:
//! `cpu::raytrace::pixel_sample`; samples of one stream are stratified
//! together, so batches of them would not be independent).
//! For a pixel channel whose terms have variance `s^2` per photon or
//! sample, halves of `n_a` and `n_b` of them differ by
//! `Var(a - b) = s^2 (1/n_a + 1/n_b)`, and the whole render's error is
//! `s^2 / (n_a + n_b)`; so the mean square of `a - b` over the image,
//! divided by `(n_a + n_b)(1/n_a + 1/n_b)`, estimates the render's mean
//! square error against the converged image (its RMSE as `compare` and
//! `diff` measure it: over the channels of every pixel). Its expectation
//! is that error exactly when the halves are independent and unbiased; in
//! one run it scatters about it (measured on sub-pixel edges and bounces,
//! docs/raytracing.md, "Budgets").

use crate::film_sums::FILM_ONE;

/// Batches both halves need before the estimate is trusted: with fewer, a
/// lucky pair of batches could stop a render far short of its budget.
pub const MIN_BATCHES: u32 = 4;

/// The halves of a render's batches, and its estimated error so far.
#[derive(Debug, Clone)]
pub struct ErrorBudget {
    /// The RMSE asked for.
    pub target: f64,
    /// The photons or samples per pixel of the whole render: each term in
    /// the film was divided by it.
    total: u32,
    /// The film's sums after the previous batch.
    last: Vec<u64>,
    halves: [Vec<u64>; 2],
    counts: [u64; 2],
    batches: u32,
    /// The latest estimate of the render's RMSE (`None` before both
    /// halves have their batches).
    pub estimate: Option<f64>,
}

impl ErrorBudget {
    /// A budget of `target` RMSE for a render of `total` photons or
    /// samples per pixel into a film of `sums` sums.
    pub fn new(target: f64, total: u32, sums: usize) -> Self {
        ErrorBudget {
            target,
            total,
            last: vec![0; sums],
            halves: [vec![0; sums], vec![0; sums]],
            counts: [0; 2],
            batches: 0,
            estimate: None,
        }
    }

    /// After a batch of `count` photons or samples per pixel, each of its
    /// own, with the film's sums so far: deals the batch's part to the
    /// half that has fewer and updates the estimate.
    pub fn add_to_smaller(&mut self, sums: &[u64], count: u32) {
        let half = usize::from(self.counts[1] < self.counts[0]);
        self.add(half, sums, count);
    }

    /// After `count` photons or samples per pixel that belong to `half`
    /// (0 or 1), with the film's sums so far: deals their part of the film
    /// to that half and updates the estimate.
    pub fn add(&mut self, half: usize, sums: &[u64], count: u32) {
        for ((last, sum), into) in self.last.iter_mut().zip(sums).zip(&mut self.halves[half]) {
            *into = into.wrapping_add(sum.wrapping_sub(*last));
            *last = *sum;
        }
        self.counts[half] += u64::from(count);
        self.batches += 1;
        self.estimate = self.estimate_now();
    }

    /// Whether the estimate is within the budget.
    pub fn reached(&self) -> bool {
        self.estimate.is_some_and(|e| e <= self.target)
    }

    fn estimate_now(&self) -> Option<f64> {
        let [n_a, n_b] = self.counts.map(|n| n as f64);
        if self.batches < MIN_BATCHES || n_a == 0.0 || n_b == 0.0 || self.last.is_empty() {
            return None;
        }
        let total = f64::from(self.total);
        let (scale_a, scale_b) = (total / n_a / FILM_ONE, total / n_b / FILM_ONE);
        let square: f64 = self.halves[0]
            .iter()
            .zip(&self.halves[1])
            .map(|(&a, &b)| (a as f64 * scale_a - b as f64 * scale_b).powi(2))
            .sum();
        let mean_square = square / self.last.len() as f64;
        Some((mean_square / ((n_a + n_b) * (1.0 / n_a + 1.0 / n_b))).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Halves drawn from a known spread give back its error: each of 20000
    /// sums gets batches of 10 terms of a fair coin (0 or 1) over 100
    /// terms in all, so the render's error is 0.5 / sqrt(n) for the n
    /// terms traced. The estimate is within 5% of it (20000 sums make its
    /// own noise about 1%), waits for MIN_BATCHES, and stops at the budget.
    #[test]
    fn the_halves_estimate_the_error_of_a_known_spread() {
        let sums = 20_000;
        let total = 100;
        // Within the budget from 60 terms (0.0645 against 0.0674), not at 50.
        let mut budget = ErrorBudget::new(0.5 / 55f64.sqrt(), total, sums);
        let mut film = vec![0u64; sums];
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut coin = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state & 1
        };
        let one_term = FILM_ONE as u64 / u64::from(total);
        let mut traced = 0;
        loop {
            for sum in film.iter_mut() {
                for _ in 0..10 {
                    *sum += coin() * one_term;
                }
            }
            traced += 10;
            budget.add_to_smaller(&film, 10);
            let reached = budget.reached();
            if traced < 40 {
                assert!(budget.estimate.is_none() && !reached);
                continue;
            }
            let truth = 0.5 / f64::from(traced).sqrt();
            let estimate = budget.estimate.unwrap();
            assert!(
                (estimate / truth - 1.0).abs() < 0.05,
                "{estimate} for {truth} at {traced}"
            );
            if reached {
                break;
            }
        }
        assert_eq!(traced, 60, "stops at the first batch within the budget");
    }
}
