//! The structural hysteresis model of a transmitting mechanical system
//! (Ruderman & Bertram 2015): a damped bedstop in series with a hysteresis
//! spring.

use hysteron_composition::{MechanicalSeries, OperatorExt, TravelLimits};
use hysteron_operators::{
    BoucWen, BoucWenParams, Float, Mms, MmsParams, Operator, ParamSet, Result, StiffnessMap,
};
use serde::{Deserialize, Serialize};

/// The transmission model: any friction element `F` (the bedstop slider,
/// travelling in a gap of size `b`) in mechanical series with any spring
/// `S`. The paper's model is [`PaperModel`]: [`Mms`] friction and the
/// [`BoucWen`] spring.
///
/// With `r` the slider position and `z = x − r` the spring deflection:
///
/// * inside the gap the slider moves and `S[z] = F[r]` (force equilibrium);
/// * at a stop, `r = ±b/2`, the spring is driven directly, `F = S[x ∓ b/2]`,
///   and the contact force `S[z] − F[r]` pushes into the stop;
/// * leaving a stop, the slider stays until the spring force has fallen to
///   the friction it meets, then slides back (its friction branch reverses).
///
/// Output: the transmitted force `F = S[z]`.
pub type Transmission<T, F, S> = MechanicalSeries<T, F, S>;

/// The paper's model: MMS friction slider in a backlash gap, in series with
/// the Bouc-Wen-like spring.
pub type PaperModel = Transmission<f64, Mms<f64>, BoucWen<f64>>;

/// Builds a transmission from any friction element and any spring: the
/// composition is a [`MechanicalSeries`] with the gap as travel limits on
/// the friction side, so swapping either part gives a working model.
///
/// `backlash` is the gap size `b > 0`; `slider0 ∈ [−b/2, b/2]` the slider's
/// initial position in it.
///
/// ```
/// use hysteron_models::transmission;
/// use hysteron_operators::{ElastoPlastic, Gain, Operator};
/// // An elastoplastic slider and a linear spring instead of the paper's parts.
/// let mut m = transmission(ElastoPlastic::new(50.0_f64, 1.0).unwrap(), Gain::new(10.0).unwrap(), 0.2, 0.0).unwrap();
/// let f = m.run(&[0.0, 0.5, 1.0]).unwrap();
/// assert!((f[2] - 10.0 * (1.0 - 0.1)).abs() < 1e-12); // at the stop: S(x − b/2)
/// ```
pub fn transmission<T, F, S>(
    friction: F,
    spring: S,
    backlash: T,
    slider0: T,
) -> Result<Transmission<T, F, S>>
where
    T: Float,
    F: Operator<T> + Clone + 'static,
    S: Operator<T> + Clone + 'static,
{
    friction.series(spring).with_limits(TravelLimits::Gap {
        b: backlash,
        r0: slider0,
    })
}

/// Parameters of the paper's model.
///
/// The paper publishes no parameter values. [`Default`] gives
/// **illustrative** values chosen to fall in the ranges of its Figure 3
/// (input within about ±1.5 deg in output coordinates, force within about
/// ±20 Nm); they are not identified from its data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransmissionParams {
    /// Backlash (gap) size `b` (deg).
    pub backlash: f64,
    /// Initial slider position in the gap, `|slider0| ≤ b/2` (deg); the
    /// spring then starts at deflection `z = −slider0`.
    #[serde(default)]
    pub slider0: f64,
    /// MMS friction on the slider: `f_c` (Nm), `k` (1/deg), initial force `y0` (Nm).
    pub friction: MmsParams<f64>,
    /// The hysteresis spring (input: deflection `z` (deg), output: force (Nm)).
    pub spring: BoucWenParams<f64>,
}

impl Default for TransmissionParams {
    // The knots are constants that satisfy the map's rules (non-negative,
    // increasing); every test that builds the default model runs it.
    #[allow(clippy::expect_used)]
    fn default() -> Self {
        Self {
            backlash: 0.3,
            slider0: 0.0,
            friction: MmsParams {
                f_c: 1.5,
                k: 30.0,
                y0: 0.0,
            },
            spring: BoucWenParams {
                w: 0.6,
                alpha: 1.0,
                beta: 2.5,
                gamma: 1.5,
                n: 1.0,
                h0: 0.0,
                z0: 0.0,
                // A hardening stiffness map S(|z|) (Nm/deg).
                stiffness: StiffnessMap::new(
                    vec![0.0, 0.3, 0.6, 0.9, 1.2, 1.5],
                    vec![10.0, 11.5, 13.5, 16.0, 19.5, 22.5],
                )
                .expect("valid default knots"),
            },
        }
    }
}

impl TransmissionParams {
    /// The spring's parameters as the model uses them: its initial input
    /// `z0` is the deflection at `x = 0`, `−slider0` (the `z0` given in
    /// [`spring`](Self::spring) is replaced).
    pub fn spring_params(&self) -> BoucWenParams<f64> {
        BoucWenParams {
            z0: 0.0 - self.slider0,
            ..self.spring.clone()
        }
    }

    /// The same model with its flat parameters (in the order of the built
    /// model's [`params`](hysteron_operators::Parameters::params): `backlash, slider0`, the
    /// friction's, the spring's) taken from the front of `p`.
    ///
    /// The spring's initial deflection is tied to the slider,
    /// `z0 = −slider0` (see [`spring_params`](Self::spring_params)): its
    /// entry must satisfy the tie, or the error names `spring.z0`. Not
    /// validated otherwise ([`build`](Self::build) does that).
    pub fn with_values(&self, p: &mut &[f64]) -> Result<Self> {
        let Some((&[backlash, slider0], tail)) = p.split_first_chunk::<2>() else {
            return Err(hysteron_operators::Error::ParamCount {
                expected: 2,
                got: p.len(),
            });
        };
        *p = tail;
        let friction = self.friction.read(p)?;
        let mut spring = self.spring_params().read(p)?;
        if spring.z0 != 0.0 - slider0 {
            return Err(hysteron_operators::Error::InvalidParameter {
                name: "spring.z0".into(),
                value: spring.z0,
                reason: "must equal −slider0 in a `transmission` spec \
                         (move slider0 and spring.z0 together)",
            });
        }
        // Not used by the model: keep what the spec said.
        spring.z0 = self.spring.z0;
        Ok(Self {
            backlash,
            slider0,
            friction,
            spring,
        })
    }

    /// Builds the paper's model from these parameters (validating all).
    pub fn build(&self) -> Result<PaperModel> {
        let friction = Mms::from_params(self.friction).map_err(|e| e.in_path("friction"))?;
        let spring = BoucWen::from_params(self.spring_params()).map_err(|e| e.in_path("spring"))?;
        transmission(friction, spring, self.backlash, self.slider0)
    }
}

/// The internal state of a [`Transmission`] after a committed sample.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct TransmissionState {
    /// Slider position in the gap, `r ∈ [−b/2, b/2]`.
    pub slider: f64,
    /// Spring deflection `z = x − r`.
    pub z: f64,
    /// Friction force on the slider.
    pub friction: f64,
    /// Hysteretic state `h` of the spring.
    pub h: f64,
}

/// Reads the internal state of the paper's model (committed values).
pub fn paper_state(model: &PaperModel, x: f64) -> TransmissionState {
    let moved = model.left_displacement();
    let r0 = match model.limits() {
        TravelLimits::Gap { r0, .. } => r0,
        _ => 0.0,
    };
    TransmissionState {
        slider: r0 + moved,
        z: x - r0 - moved,
        friction: model.left().output(),
        h: model.right().state(),
    }
}
