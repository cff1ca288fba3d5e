//! Measurements that must agree with a repeat before they count: a row is measured on one
//! executor, then on another built afresh, until two of them agree.
//!
//! On the H100 and the H200 an executor sometimes runs every one of its passes 2-3x slower
//! than the next executor of the same graph, scene-independent passes (the tone map) included,
//! with the SM clock at its maximum (BENCHMARKS.md, "One row, two executors"). Its frames are
//! slow and steady, so the warm-up's settling test ([`crate::runtime::warm_up`]) passes them.
//! Such a row is told apart only by measuring it again: a second executor that agrees within
//! the tolerance confirms the first; one that does not calls for a third, and so on up to a
//! limit.

/// How many executors a row may take and how close two must agree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Repeats {
    /// Executors measured at most for one row (1: no repeat).
    pub max_executors: usize,
    /// Two measurements agree when they differ by at most this fraction of the faster.
    pub tolerance: f64,
}

impl Repeats {
    /// On a hardware GPU: up to four executors, agreeing within 3% (the rule of BENCHMARKS.md:
    /// two runs of a bench agree within 3%).
    pub const GPU: Repeats = Repeats { max_executors: 4, tolerance: 0.03 };
    /// On a software adapter (lavapipe) the figures are not claims and the slow executors were
    /// never seen: one executor.
    pub const SOFTWARE: Repeats = Repeats { max_executors: 1, tolerance: 0.10 };

    /// The policy for `gpu`'s adapter.
    pub fn for_gpu(gpu: &crate::runtime::Gpu) -> Repeats {
        if gpu.info().device_type == wgpu::DeviceType::Cpu {
            Repeats::SOFTWARE
        } else {
            Repeats::GPU
        }
    }

    /// Which of the measurements so far (`ms`, in order) the row reports, or `None` when
    /// another executor is needed: the faster of the closest pair that agrees; with no pair
    /// agreeing after [`Self::max_executors`], the median (the upper one of an even count).
    pub fn chosen(&self, ms: &[f64]) -> Option<usize> {
        let agree = |a, b| self.agree(a, b);
        let mut best: Option<(f64, usize)> = None;
        for i in 0..ms.len() {
            for j in i + 1..ms.len() {
                let gap = (ms[i] - ms[j]).abs();
                if agree(ms[i], ms[j]) && best.is_none_or(|(g, _)| gap < g) {
                    best = Some((gap, if ms[i] <= ms[j] { i } else { j }));
                }
            }
        }
        if let Some((_, k)) = best {
            return Some(k);
        }
        if ms.len() >= self.max_executors.max(1) {
            let mut order: Vec<usize> = (0..ms.len()).collect();
            order.sort_by(|&a, &b| ms[a].total_cmp(&ms[b]));
            return Some(order[ms.len() / 2]);
        }
        None
    }

    /// Whether some two of `ms` agree within the tolerance (a row chosen by the median when
    /// none do is told apart in the tables: `bench rays` marks it).
    pub fn agreed(&self, ms: &[f64]) -> bool {
        (0..ms.len()).any(|i| (i + 1..ms.len()).any(|j| self.agree(ms[i], ms[j])))
    }

    /// Two measurements agree: they differ by at most the tolerance of the faster.
    fn agree(&self, a: f64, b: f64) -> bool {
        (a - b).abs() <= self.tolerance * a.min(b)
    }

    /// Runs `measure` (one executor's measurement and its GPU ms) until [`Self::chosen`] picks
    /// one; returns it and every executor's GPU ms in order.
    pub fn run<T, E>(&self, mut measure: impl FnMut() -> Result<(T, f64), E>) -> Result<(T, Vec<f64>), E> {
        let (mut values, mut ms) = (Vec::new(), Vec::new());
        loop {
            let (value, t) = measure()?;
            values.push(Some(value));
            ms.push(t);
            if let Some(k) = self.chosen(&ms) {
                let value = values[k].take().expect("each measurement is taken once");
                return Ok((value, ms));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_executor_is_enough_on_a_software_adapter() {
        assert_eq!(Repeats::SOFTWARE.chosen(&[5.0]), Some(0));
    }

    #[test]
    fn a_slow_executor_is_measured_again_and_left_out() {
        // The box row of 2026-11-29: 5.876 ms on one executor, 1.922 on the next ones.
        let p = Repeats::GPU;
        assert_eq!(p.chosen(&[5.876]), None);
        assert_eq!(p.chosen(&[5.876, 1.922]), None, "3x apart: a third executor");
        assert_eq!(p.chosen(&[5.876, 1.922, 1.923]), Some(1), "the faster of the pair that agrees");
    }

    #[test]
    fn two_agreeing_executors_end_the_row_with_the_faster() {
        assert_eq!(Repeats::GPU.chosen(&[6.75, 6.72]), Some(1));
        assert_eq!(Repeats::GPU.chosen(&[6.72, 6.75]), Some(0));
        // 3% of the faster: 1.00 and 1.029 agree, 1.00 and 1.031 do not.
        assert_eq!(Repeats::GPU.chosen(&[1.0, 1.029]), Some(0));
        assert_eq!(Repeats::GPU.chosen(&[1.0, 1.031]), None);
    }

    #[test]
    fn the_closest_pair_wins_when_several_agree() {
        // 10.0 and 10.25 agree (2.5%), 10.25 and 10.26 agree more closely.
        assert_eq!(Repeats::GPU.chosen(&[10.0, 10.25, 10.26]), Some(1));
    }

    #[test]
    fn no_agreement_within_the_limit_gives_the_median() {
        let p = Repeats::GPU;
        assert_eq!(p.chosen(&[1.0, 2.0, 4.0]), None);
        assert_eq!(p.chosen(&[1.0, 2.0, 4.0, 8.0]), Some(2), "the upper median of four: 4.0");
    }

    #[test]
    fn agreed_tells_a_median_row_from_a_confirmed_one() {
        let p = Repeats::GPU;
        // helmet_5x5x5 at 2% on the H200, 2026-12-01 07:10 UTC: four executors, none within 3%.
        assert!(!p.agreed(&[6.720, 9.277, 10.318, 2.282]));
        assert!(p.agreed(&[2.283, 2.282]));
        assert!(p.agreed(&[5.876, 1.922, 1.923]));
        assert!(!p.agreed(&[5.0]), "one executor confirms nothing");
    }

    #[test]
    fn run_measures_until_two_agree_and_returns_every_time() {
        let times = [5.9, 1.92, 1.93, 1.0];
        let mut k = 0;
        let (chosen, all) = Repeats::GPU
            .run(|| {
                k += 1;
                Ok::<_, ()>((k, times[k - 1]))
            })
            .unwrap();
        assert_eq!(all, vec![5.9, 1.92, 1.93]);
        assert_eq!(chosen, 2, "the second measurement, the faster of the agreeing pair");
    }
}
