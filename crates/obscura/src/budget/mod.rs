//! [`BudgetController`]: holds a frame-time budget by choosing, each frame, one of a ladder
//! of AO settings ordered from cheapest to dearest (seed 002: Yang, Sander & Lawrence's
//! geometry-aware framebuffer level of detail adapts the shading resolution to a target
//! frame time every frame).
//!
//! The controller sees only the measured time of each frame and the level it ran at, so it
//! works with any clock (GPU timestamps, or the wall clock around submit and wait on CPU
//! adapters) and any ladder (sample counts, resolutions, layouts). It is model-predictive
//! with hysteresis rather than a PI loop on a continuous variable: with discrete levels a PI
//! loop whose target lies between two levels' costs cycles between them. Instead:
//!
//! - The time of a frame is modelled as `scene × cost[level]`: `cost` is each level's
//!   relative cost, the mean of the first [`SETTLE_FRAMES`] frames after each switch to it
//!   against the scene as it stood (the caller's nominal ratios until then), and `scene`
//!   is the current scene's complexity, an exponential average of `time / cost[level]`
//!   over the frames after those (weight [`SCENE_SMOOTHING`]), so a change of view moves
//!   every level's prediction at once. A view that changes during a level's settling
//!   frames is booked to that level's cost until its next visit (the two cannot be told
//!   apart from one level's times); the level is then tried again only once the scene has
//!   become cheaper by as much.
//! - Down: a frame whose smoothed time is over `budget × (1 + DOWN_TOLERANCE)` drops to the
//!   dearest level predicted within the budget (at least one level down).
//! - Up: to the dearest level predicted within `budget × (1 − UP_MARGIN)`, once the
//!   current level has held for [`SETTLE_FRAMES`] frames. A level that went over the
//!   budget is not tried again until the scene's complexity has fallen by the margin since
//!   (its measured cost says so). With nominal costs measured beforehand (one timed frame
//!   per level) the first prediction is already right.
//!
//! Between the two thresholds nothing changes, so a budget that falls between two levels'
//! costs settles on the cheaper one instead of alternating.
//!
//! [`ScaleController`] holds a budget with one continuous knob instead, the working scale of
//! [`crate::Resolution::Scaled`] (the design in docs/budget.md): an integral
//! controller on the log of the working area s², with a dead band for hysteresis.
//!
//! [`JointController`] turns both knobs, the working scale and the sample count: the scale
//! up to a top scale, then a ladder of full-resolution sample counts above it, handing over
//! between the two with the ladder's hysteresis.

/// Smoothing of the scene complexity: weight of the newest frame.
pub const SCENE_SMOOTHING: f64 = 0.3;
/// A smoothed frame time more than this fraction over the budget steps down.
pub const DOWN_TOLERANCE: f64 = 0.05;
/// A level is tried only if it is predicted at least this fraction under the budget.
pub const UP_MARGIN: f64 = 0.1;
/// Frames a level holds before the controller may step up from it.
pub const SETTLE_FRAMES: u32 = 3;

/// Chooses each frame's level of a ladder to hold a frame-time budget; see the module
/// documentation.
#[derive(Clone, Debug)]
pub struct BudgetController {
    budget_ms: f64,
    /// The caller's nominal relative cost of each level (cheapest first).
    nominal: Vec<f64>,
    /// Learned relative cost of each level (meaningful where `measured`).
    cost: Vec<f64>,
    /// Whether each level has run a frame.
    measured: Vec<bool>,
    /// Smoothed `time / cost` of the recent frames; `None` before the first frame.
    scene: Option<f64>,
    level: usize,
    held: u32,
}

impl BudgetController {
    /// A controller for `budget_ms` per frame over levels whose nominal relative costs are
    /// `nominal_costs` (cheapest first, each > 0, e.g. samples per full-resolution pixel).
    /// It starts at the cheapest level. `None` if the budget is not a positive finite number
    /// or a cost is not a positive finite number, or the ladder is empty.
    pub fn new(budget_ms: f64, nominal_costs: &[f64]) -> Option<Self> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(budget_ms) || nominal_costs.is_empty() || !nominal_costs.iter().all(|&c| ok(c)) {
            return None;
        }
        Some(Self {
            budget_ms,
            nominal: nominal_costs.to_vec(),
            cost: nominal_costs.to_vec(),
            measured: vec![false; nominal_costs.len()],
            scene: None,
            level: 0,
            held: 0,
        })
    }

    /// The level to run this frame (0 = cheapest).
    pub fn level(&self) -> usize {
        self.level
    }

    /// The budget in milliseconds per frame.
    pub fn budget_ms(&self) -> f64 {
        self.budget_ms
    }

    /// The predicted time of `level` for the current scene, once a frame has been measured.
    pub fn predicted_ms(&self, level: usize) -> Option<f64> {
        if level >= self.cost.len() {
            return None;
        }
        Some(self.scene? * self.cost_of(level))
    }

    /// A level's relative cost: learned, or else the nominal ratio to the nearest measured
    /// level (below first).
    fn cost_of(&self, level: usize) -> f64 {
        if self.measured[level] {
            return self.cost[level];
        }
        let below = (0..level).rev().find(|&m| self.measured[m]);
        match below.or_else(|| (level + 1..self.cost.len()).find(|&m| self.measured[m])) {
            Some(m) => self.cost[m] * self.nominal[level] / self.nominal[m],
            None => self.nominal[level],
        }
    }

    /// Reports the measured time of the frame just run at [`Self::level`] and returns the
    /// level for the next frame. Times that are not finite and positive (a failed or
    /// unsupported timestamp read as 0) are ignored.
    pub fn update(&mut self, measured_ms: f64) -> usize {
        if !(measured_ms.is_finite() && measured_ms > 0.0) {
            return self.level;
        }
        let k = self.level;
        let scene = match self.scene {
            // The first frame sets the scene from the nominal cost.
            None => measured_ms / self.cost[k],
            // The first SETTLE_FRAMES frames after a switch measure the level's cost (their
            // mean) against the scene as it stood (views change slowly next to a few
            // frames; one frame's time on a CPU adapter varies by ±20%).
            Some(s) if self.held < SETTLE_FRAMES => {
                let n = self.held as f64;
                let sample = (measured_ms / s).max(f64::MIN_POSITIVE);
                self.cost[k] = if n == 0.0 {
                    sample
                } else {
                    (self.cost[k] * n + sample) / (n + 1.0)
                };
                s
            }
            // Later frames at the level: the scene explains them.
            Some(s) => s + SCENE_SMOOTHING * (measured_ms / self.cost[k] - s),
        };
        self.scene = Some(scene);
        self.measured[k] = true;
        self.held += 1;
        let smoothed = scene * self.cost[k];
        if smoothed > self.budget_ms * (1.0 + DOWN_TOLERANCE) && k > 0 {
            // The dearest cheaper level predicted within the budget (else the cheapest).
            let fit = (0..k)
                .rev()
                .find(|&j| scene * self.cost_of(j) <= self.budget_ms)
                .unwrap_or(0);
            self.set(fit);
        } else if self.held >= SETTLE_FRAMES {
            // The dearest dearer level predicted within the margin, if any.
            let fit = (k + 1..self.cost.len())
                .rev()
                .find(|&j| scene * self.cost_of(j) <= self.budget_ms * (1.0 - UP_MARGIN));
            if let Some(j) = fit {
                self.set(j);
            }
        }
        self.level
    }

    fn set(&mut self, level: usize) {
        if level != self.level {
            self.level = level;
            self.held = 0;
        }
    }

    /// Starts again at the cheapest level with no scene estimate (the frames in between ran
    /// something else); the learned level costs are kept.
    fn enter_at_bottom(&mut self) {
        self.level = 0;
        self.held = 0;
        self.scene = None;
    }
}

/// The scale controller's gain: each frame moves ln s² by this fraction of ln(budget /
/// time). Below 1, so a cost affine in s² with a non-negative floor never overshoots.
pub const SCALE_GAIN: f64 = 0.5;
/// Frames within this fraction of the budget (in ln time) leave the scale as it is.
pub const SCALE_DEAD_BAND: f64 = 0.03;

/// Chooses each frame's working scale of [`crate::Resolution::Scaled`] in
/// [[`crate::MIN_SCALE`], 1] to hold a frame-time budget.
///
/// The AO's cost is close to affine in the working area x = s²: `time = floor + c × x`, the
/// floor being the passes at full resolution (prepare, the upsampler) and per-pass
/// overheads. Each frame the controller sets
/// `x ← x × (budget / time)^SCALE_GAIN` (an integral controller on ln x), unless the time
/// is within [`SCALE_DEAD_BAND`] of the budget. The loop gain is `SCALE_GAIN × d ln time /
/// d ln x`, and for an affine cost `d ln time / d ln x = c x / time` lies in [0, 1]: the
/// scale approaches its target without overshoot, faster the smaller the floor, and a
/// frame's timing noise moves the next scale by only half as much. No model is learned, so
/// a change of view needs no special case.
#[derive(Clone, Debug)]
pub struct ScaleController {
    budget_ms: f64,
    /// The working area s², in [MIN_SCALE², max_area].
    area: f64,
    /// The largest working area the controller chooses (1 unless
    /// [`Self::with_max_scale`] says otherwise).
    max_area: f64,
}

impl ScaleController {
    /// A controller for `budget_ms` per frame starting at scale `start` (clamped to
    /// [MIN_SCALE, 1]). `None` if the budget is not a positive finite number or `start` is
    /// not finite.
    pub fn new(budget_ms: f64, start: f32) -> Option<Self> {
        if !(budget_ms.is_finite() && budget_ms > 0.0 && start.is_finite()) {
            return None;
        }
        let s = f64::from(start.clamp(crate::MIN_SCALE, 1.0));
        Some(Self {
            budget_ms,
            area: s * s,
            max_area: 1.0,
        })
    }

    /// The same controller choosing scales up to `max` (clamped to [MIN_SCALE, 1]); the
    /// current scale is clamped to it.
    pub fn with_max_scale(mut self, max: f32) -> Self {
        let m = f64::from(max.clamp(crate::MIN_SCALE, 1.0));
        self.max_area = m * m;
        self.area = self.area.min(self.max_area);
        self
    }

    /// The largest scale the controller chooses.
    pub fn max_scale(&self) -> f32 {
        self.max_area.sqrt() as f32
    }

    /// Moves the scale to `s` (clamped to [MIN_SCALE, the maximum]); the next frames go on
    /// from there.
    pub fn set_scale(&mut self, s: f32) {
        let min = f64::from(crate::MIN_SCALE).powi(2);
        let s = f64::from(if s.is_finite() { s } else { crate::MIN_SCALE });
        self.area = (s * s).clamp(min, self.max_area);
    }

    /// The scale to run this frame ([`crate::AoParams::scale`]).
    pub fn scale(&self) -> f32 {
        (self.area.sqrt() as f32).clamp(crate::MIN_SCALE, 1.0)
    }

    /// The budget in milliseconds per frame.
    pub fn budget_ms(&self) -> f64 {
        self.budget_ms
    }

    /// Reports the measured time of the frame just run at [`Self::scale`] and returns the
    /// scale for the next frame. Times that are not finite and positive are ignored.
    pub fn update(&mut self, measured_ms: f64) -> f32 {
        if measured_ms.is_finite() && measured_ms > 0.0 {
            let error = (self.budget_ms / measured_ms).ln();
            if error.abs() > SCALE_DEAD_BAND {
                let min = f64::from(crate::MIN_SCALE).powi(2);
                self.area = (self.area * (SCALE_GAIN * error).exp()).clamp(min, self.max_area);
            }
        }
        self.scale()
    }
}

/// What [`JointController`] runs this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Knob {
    /// The scaled AO ([`crate::Resolution::Scaled`]) at this working scale.
    Scale(f32),
    /// This level of the full-resolution ladder (0 = cheapest).
    Level(usize),
}

/// Holds a frame-time budget with both knobs: the working scale, then the
/// sample count.
///
/// Below a top scale the frame runs one scaled AO whose scale a [`ScaleController`] turns
/// (capped at the top); above it, a ladder of full-resolution levels (sample counts,
/// cheapest first) that a [`BudgetController`] chooses among. The order is measured, not
/// assumed: on lavapipe the scaled path costs three passes more than full resolution, and
/// at equal time a full-resolution frame at 16 or more samples per pixel beats the scaled
/// one above about scale 0.65–0.75, while below that the scale is the cheaper knob (the
/// samples cost little next to the fixed passes; docs/budget.md, "Both knobs"). The caller
/// places the top where the scaled AO costs what ladder level 0 does (`handover` = that
/// level's cost over the scaled AO's at the top, nominally 1). The handover ratio is then
/// learned at each climb: the mean of ladder level 0's frames until it settles
/// ([`SETTLE_FRAMES`]) or is left, over the mean of the frames at the top that led to it
/// (the view changes little in a few frames), so a wrong nominal ratio costs one try, not
/// a cycle. (A rung left after one frame teaches the ratio from that frame alone; a frame
/// slowed by the machine then holds the scale at the top until the view gets cheaper by
/// as much.)
///
/// Handing over, with the ladder's hysteresis:
/// - **Up**: after [`SETTLE_FRAMES`] consecutive frames at the top scale each predicted to
///   fit ladder level 0 with [`UP_MARGIN`] to spare (`time × handover`), the ladder starts
///   at level 0 with its learned costs, and climbs as a [`BudgetController`] does.
/// - **Down**: when the ladder sits on level 0 and its smoothed time is more than
///   [`DOWN_TOLERANCE`] over the budget, the scale resumes at the top scale times the
///   square root of budget / predicted time (the whole time taken as proportional to the
///   working area: with fixed passes that under-corrects, by the floor times (1 − budget /
///   time), and the scale's integral finishes the descent).
#[derive(Clone, Debug)]
pub struct JointController {
    scale: ScaleController,
    ladder: BudgetController,
    handover: f64,
    on_ladder: bool,
    /// Consecutive frames at the top scale predicted to fit ladder level 0, and their sum
    /// of times.
    fits: u32,
    fits_ms: f64,
    /// Since the last climb: the mean time of the frames at the top before it, and the
    /// count and sum of ladder level 0's frames after it (while it is still learning).
    climb: Option<(f64, u32, f64)>,
}

impl JointController {
    /// A controller for `budget_ms` starting on the scale at `start` (clamped to the top),
    /// with scales up to `top` and above them the ladder of `ladder_costs` (relative,
    /// cheapest first, as [`BudgetController::new`]), `handover` being ladder level 0's cost
    /// over the scaled AO's at `top`. `None` if the budget, a cost or `handover` is not a
    /// positive finite number, `start` or `top` is not finite, or the ladder is empty.
    pub fn new(
        budget_ms: f64,
        start: f32,
        top: f32,
        ladder_costs: &[f64],
        handover: f64,
    ) -> Option<Self> {
        if !(handover.is_finite() && handover > 0.0 && top.is_finite()) {
            return None;
        }
        Some(Self {
            scale: ScaleController::new(budget_ms, start)?.with_max_scale(top),
            ladder: BudgetController::new(budget_ms, ladder_costs)?,
            handover,
            on_ladder: false,
            fits: 0,
            fits_ms: 0.0,
            climb: None,
        })
    }

    /// What to run this frame.
    pub fn knob(&self) -> Knob {
        if self.on_ladder {
            Knob::Level(self.ladder.level())
        } else {
            Knob::Scale(self.scale.scale())
        }
    }

    /// The largest scale before the ladder.
    pub fn top_scale(&self) -> f32 {
        self.scale.max_scale()
    }

    /// Ladder level 0's cost over the scaled AO's at the top scale, as last learned.
    pub fn handover(&self) -> f64 {
        self.handover
    }

    /// Learns the handover ratio from the frames since the climb, once.
    fn learn_handover(&mut self) {
        if let Some((top_ms, n, sum)) = self.climb.take() {
            if n > 0 {
                self.handover = sum / f64::from(n) / top_ms;
            }
        }
    }

    /// Reports the measured time of the frame just run at [`Self::knob`] and returns the knob
    /// for the next frame. Times that are not finite and positive are ignored.
    pub fn update(&mut self, measured_ms: f64) -> Knob {
        if !(measured_ms.is_finite() && measured_ms > 0.0) {
            return self.knob();
        }
        let budget = self.scale.budget_ms();
        if self.on_ladder {
            let level = self.ladder.level();
            if level == 0 {
                if let Some((_, n, sum)) = &mut self.climb {
                    *n += 1;
                    *sum += measured_ms;
                }
            }
            let next = self.ladder.update(measured_ms);
            if level != 0 || next != 0 || self.climb.is_some_and(|c| c.1 >= SETTLE_FRAMES) {
                self.learn_handover();
            }
            let smoothed = self.ladder.predicted_ms(0).unwrap_or(measured_ms);
            if level == 0 && next == 0 && smoothed > budget * (1.0 + DOWN_TOLERANCE) {
                self.learn_handover();
                let at_top = smoothed / self.handover;
                let s = f64::from(self.scale.max_scale()) * (budget / at_top).sqrt();
                self.scale.set_scale(s as f32);
                self.on_ladder = false;
                self.fits = 0;
                self.fits_ms = 0.0;
            }
        } else {
            let at_top = self.scale.scale() >= self.scale.max_scale();
            if at_top && measured_ms * self.handover <= budget * (1.0 - UP_MARGIN) {
                self.fits += 1;
                self.fits_ms += measured_ms;
            } else {
                self.fits = 0;
                self.fits_ms = 0.0;
            }
            if self.fits >= SETTLE_FRAMES {
                self.climb = Some((self.fits_ms / f64::from(self.fits), 0, 0.0));
                self.ladder.enter_at_bottom();
                self.on_ladder = true;
            } else {
                self.scale.update(measured_ms);
            }
        }
        self.knob()
    }
}

#[cfg(test)]
mod tests;
