//! Where a load stage's walk over its load parameter `t ∈ [0, 1]` stands ([`StageWalk`]): the
//! stage loop ([`super::stage`]) advances it step by step, and a checkpoint
//! ([`super::checkpoint`]) keeps it, so that a resumed stage continues where it stood: at the
//! same `t`, with the same next increment and the same predictor of the step after a break.
use super::records::LoadPoint;
use super::step_predictor::StepPredictor;

/// Where a stage's walk stands: the committed `t`, the next increment `h` (halved on a
/// cut-back, doubled after a success up to the step), whether the trial ends at a contact
/// event, and the response of the last step cut by a break.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub(super) struct StageWalk {
    from: LoadPoint,
    /// The stage's load at `t = 1`.
    pub(super) target: LoadPoint,
    /// Steps of the stage.
    n: f64,
    /// The stage's step `1/n`.
    pub(super) step: f64,
    /// The smallest increment: the step after `max_cutbacks` halvings.
    h_min: f64,
    /// The committed load parameter.
    pub(super) t: f64,
    /// The next increment.
    pub(super) h: f64,
    /// The trial already ends at a contact event: it is not cut again (no Zeno steps).
    pub(super) at_event: bool,
    /// The response of the last step cut by a break ([`super::step_predictor`]).
    pub(super) predictor: Option<StepPredictor>,
    /// The recorded states when the stage began: its loss-of-load watch starts there.
    pub(super) records_at_start: usize,
}

impl StageWalk {
    /// A walk from `from` (at `t = 0`) to `target` in `steps` steps, each halved at most
    /// `max_cutbacks` times; `records_at_start` states were recorded before the stage.
    pub(super) fn new(
        from: LoadPoint,
        target: LoadPoint,
        steps: usize,
        max_cutbacks: usize,
        records_at_start: usize,
    ) -> StageWalk {
        let n = steps.max(1) as f64;
        let step = 1.0 / n;
        let h_min = step * 0.5f64.powi(max_cutbacks as i32);
        StageWalk { from, target, n, step, h_min, t: 0.0, h: step, at_event: false, predictor: None, records_at_start }
    }

    /// The stage's end is reached.
    pub(super) fn done(&self) -> bool {
        self.t >= 1.0 - 1e-12
    }

    /// The load at `t`.
    pub(super) fn load_at(&self, t: f64) -> LoadPoint {
        LoadPoint::lerp(&self.from, &self.target, t)
    }

    /// The end of the next trial: `t + h`, never past the next step boundary (the recorded curve
    /// keeps its regular points) and without slivers from round-off.
    pub(super) fn trial_end(&self) -> f64 {
        let boundary = (((self.t * self.n) + 1e-9).floor() + 1.0) / self.n;
        let t_try = (self.t + self.h).min(boundary).min(1.0);
        if boundary - t_try < 1e-9 * self.step {
            boundary
        } else {
            t_try
        }
    }

    /// The increment can be halved once more.
    pub(super) fn can_halve(&self) -> bool {
        self.h * 0.5 >= self.h_min
    }

    /// The trial to `t_try` is retried with half its increment.
    pub(super) fn halve(&mut self, t_try: f64) {
        self.h = 0.5 * (t_try - self.t);
    }
}
