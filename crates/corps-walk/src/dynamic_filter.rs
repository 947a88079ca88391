//! Dynamic filter (seed 002 §4.5, Naveau et al. 2017 after Kajita et al. 2003): the LIPM plan
//! neglects the limbs' momentum, so the multibody ZMP `p_MB` of the planned motion (computed
//! elsewhere by inverse kinematics + RNEA on the whole-body model) differs from the reference
//! `p_ref`. The error `Δp = p_ref − p_MB` over the preview window is fed to a preview
//! controller as the ZMP reference of a cart-table whose CoM is the correction `Δc`; since the
//! multibody ZMP responds to a small CoM shift like the cart-table does, `c + Δc` brings the
//! multibody ZMP back onto `p_ref`. One pass per tick, as in jrl-walkgen (seed 002 §4.5: a
//! single iteration; corrections up to 5 cm on Pyrène).

use crate::preview_control::{PreviewAxis, PreviewController, PreviewParams};
use crate::WalkError;
use nalgebra::Vector3;

/// CoM correction by preview control of the multibody ZMP error.
#[derive(Debug, Clone)]
pub struct DynamicFilter {
    controller: PreviewController,
    x: PreviewAxis,
    y: PreviewAxis,
}

impl DynamicFilter {
    /// A filter with Kajita preview control (integral action) of parameters `params`.
    pub fn new(params: &PreviewParams) -> Result<Self, WalkError> {
        Ok(Self {
            controller: PreviewController::with_integral(params)?,
            x: PreviewAxis::default(),
            y: PreviewAxis::default(),
        })
    }

    /// Preview samples `N`: the error windows must hold `N + 1` samples.
    pub fn horizon(&self) -> usize {
        self.controller.horizon()
    }

    /// Resets the correction to zero.
    pub fn reset(&mut self) {
        self.x = PreviewAxis::default();
        self.y = PreviewAxis::default();
    }

    /// Current correction `[Δc, Δċ, Δc̈]` per axis (to add to the planned CoM).
    pub fn correction(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.x.x, self.y.x)
    }

    /// One period: `error_x[j]`, `error_y[j]` are `Δp(k + j)`, `j = 0..=N`. Returns the
    /// correction for the next period. Never allocates.
    pub fn step(
        &mut self,
        error_x: &[f64],
        error_y: &[f64],
    ) -> Result<(Vector3<f64>, Vector3<f64>), WalkError> {
        self.controller.step(&mut self.x, error_x)?;
        self.controller.step(&mut self.y, error_y)?;
        Ok(self.correction())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Synthetic multibody error: the whole-body ZMP is the LIPM ZMP plus a 2 cm step
    /// disturbance `d` from t = 2 s (order of the 5 cm corrections of seed 002 §4.5). The filter
    /// sees `Δp = p_ref − p_MB = −d` over its window; the corrected multibody ZMP
    /// `p_ref + p_lipm(Δc) + d` must converge to `p_ref` (integral action: zero steady-state
    /// error; we require the residual below 1 % of the step) and its worst error must be below
    /// the uncorrected one (|d|).
    #[test]
    fn cancels_a_step_zmp_error() {
        let p = crate::test_fixtures::talos_preview();
        let mut f = DynamicFilter::new(&p).unwrap();
        let n = f.horizon();
        let d = |t: f64| if t >= 2.0 { 0.02 } else { 0.0 };
        let model = PreviewController::with_integral(&p).unwrap().model;
        let mut ex = vec![0.0; n + 1];
        let ey = vec![0.0; n + 1];
        let (mut worst, mut last) = (0.0f64, 0.0);
        for k in 0..2000 {
            let t = k as f64 * p.period;
            for (j, e) in ex.iter_mut().enumerate() {
                *e = -d(t + j as f64 * p.period);
            }
            let (cx, _) = f.correction();
            let corrected_error = model.zmp(&cx) + d(t); // p_MB(corrected) − p_ref
            worst = worst.max(corrected_error.abs());
            last = corrected_error;
            f.step(&ex, &ey).unwrap();
        }
        eprintln!("dynamic filter: worst corrected ZMP error {worst:.4} m (uncorrected 0.02), final {last:.2e}");
        assert!(last.abs() < 0.01 * 0.02);
        assert!(worst < 0.02);
        // the CoM correction moves against the disturbance by about its size
        assert!((f.correction().0[0] + 0.02).abs() < 1e-3);
    }
}
