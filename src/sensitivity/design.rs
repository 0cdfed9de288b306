//! [`SobolDesign`]: the pick-freeze design of Sobol' indices as one vector run of the engine.

use std::sync::{Arc, Mutex, OnceLock};

use super::indices::{Indices, OutputIndices, SecondOrder};
use super::layout::Layout;
use crate::error::{Error, Result};
use crate::estimator::BatchVectorUniformEstimator;
use crate::integrate::{Integrator, VectorRun};
use crate::measure::Measure;
use crate::pdf::UniformBox;
use crate::points::Points;
use crate::sampler::{Scramble, Sobol};
use crate::stats::{Tolerance, VectorEstimate, Warning, unrepresentable_output};

/// Points of the design unless [`SobolDesign::points`] says otherwise.
pub const DEFAULT_POINTS: u64 = 1 << 16;
/// Independently scrambled sequences the points are split into, unless
/// [`SobolDesign::replicates`] says otherwise.
pub const DEFAULT_REPLICATES: u64 = 8;

/// The design's integrand over the unit cube, on blocks of points: every model output's
/// block of integrals.
///
/// ```
/// use mcint::sensitivity::DesignIntegrand;
/// use mcint::Points;
/// // Output k of point i goes to out[k * n + i].
/// let f: DesignIntegrand = Box::new(|p: &Points, out: &mut [f64]| out.copy_from_slice(p.column(0)));
/// let mut points = Points::new(1, 2).unwrap();
/// points.column_mut(0)[1] = 0.5;
/// let mut out = [1.0; 2];
/// f(&points, &mut out);
/// assert_eq!(out, [0.0, 0.5]);
/// ```
pub type DesignIntegrand = Box<dyn Fn(&Points, &mut [f64]) + Send + Sync>;

/// The run of a design, as [`SobolDesign::integrator`] returns it: an [`Integrator`] of the
/// design's integrand, to configure further (seed, threads, limits) and run.
///
/// ```
/// use mcint::{measure::Uniform, sensitivity::{DesignRun, SobolDesign}};
/// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
/// let run: DesignRun = design.integrator(|x: &[f64]| x[0]).unwrap().threads(1);
/// assert_eq!(run.run().unwrap().outputs.len(), 8);
/// ```
pub type DesignRun = Integrator<VectorRun<BatchVectorUniformEstimator<DesignIntegrand>>>;

/// The Sobol' indices of a model `Y = f(X)` whose inputs `X` follow a probability law seen
/// from the unit cube (a [`Measure`] of weight 1: [`Uniform`], [`Gaussian`], [`Lognormal`],
/// inputs given by their quantile functions with [`Independent`], ...), by the pick-freeze
/// design of Saltelli et al. (2010).
///
/// Each point `u` of the unit cube of twice the law's canonical dimension `k` gives two
/// independent inputs, `A` from `u[..k]` and `B` from `u[k..]`, and for each factor `j` (an
/// input, or a group of inputs) the mixed input `AB_j`: `A` with the factor's coordinates
/// taken from `B` (and `BA_j`, its mirror, for second order). The model runs `2 + F` times per
/// point for `F` factors (`2 + 2F` with second order), and the run integrates the products
/// whose means are the partial variances; every index is then a smooth function of those
/// integrals with a delta-method error bar. The factors are the law's canonical coordinates
/// (independent uniforms); for a law with independent coordinates ([`Uniform`],
/// [`Independent`], a [`Gaussian`] with diagonal covariance) these are the inputs themselves.
/// For a correlated [`Gaussian`] with the Cholesky factorization, coordinate `i` is the part of
/// `x_i` not explained by `x_1 .. x_{i-1}`, so the indices are those of that ordering.
///
/// [`integrator`](Self::integrator) gives the run as an [`Integrator`], with every setting
/// the crate's runs share (seed, threads, time limits, MPI clusters, and for a fixed budget
/// checkpoints with [`run_part`](Integrator::run_part)), and [`indices`](Self::indices) turns its
/// result into the indices.
///
/// **Points and error bars.** By default the design's [`DEFAULT_POINTS`] points are
/// [`DEFAULT_REPLICATES`] independent Sobol' sequences, each with Matoušek's linear matrix
/// scramble and a digital shift (the scramble of scipy and SALib), and the error bars come
/// from the spread between them, with Student-t quantiles: over hundreds of seeds they cover
/// at the nominal rate and are about 3-4 times the median actual error. The price is
/// accuracy: on one sequence the total-index integrand's error falls about as fast as `N^-2`,
/// so one sequence of all the points (`replicates(1)`, as SALib samples) is several times
/// more accurate, but has no error bar (the spread of batches of one sequence was measured as
/// an alternative, and is neither tight nor reliable; `docs/measurements.md`).
///
/// ```
/// use mcint::{sensitivity::SobolDesign, testfns::Ishigami};
/// let ishigami = Ishigami::new(7.0, 0.1).unwrap();
/// let design = SobolDesign::new(ishigami.inputs()).unwrap();
/// let run = design.integrator(move |x: &[f64]| ishigami.eval(x)).unwrap().seed(1).run().unwrap();
/// let indices = design.indices(&run).unwrap();
/// let exact = ishigami.exact_indices();
/// for j in 0..3 {
///     let (s, st) = (&indices.first_order()[j], &indices.total()[j]);
///     assert!((s.mean - exact.first_order[j]).abs() < 5.0 * s.std_error.unwrap());
///     assert!((st.mean - exact.total[j]).abs() < 5.0 * st.std_error.unwrap());
/// }
/// ```
///
/// [`Gaussian`]: crate::measure::Gaussian
/// [`Lognormal`]: crate::measure::Lognormal
/// [`Independent`]: crate::measure::Independent
/// [`Uniform`]: crate::measure::Uniform
pub struct SobolDesign<M> {
    inputs: Arc<M>,
    factors: Arc<Vec<Vec<usize>>>,
    second_order: bool,
    tolerance: Option<Tolerance>,
    points: u64,
    replicates: Option<u64>,
    /// The model outputs of every integrator the design built: a run must have the outputs
    /// of one of them (a run of another design may have a multiple of this one's block).
    built: Mutex<Vec<usize>>,
}

impl<M: Measure + 'static> SobolDesign<M> {
    /// The design over the law `inputs`, one factor per canonical coordinate, first-order and
    /// total indices.
    ///
    /// Errors when `inputs` is not a probability law: its weight is not 1 at one of a few
    /// fixed points of the cube (the centre, a corner region, a spread point), as for an
    /// unbounded Lebesgue measure, which can have weight 1 at the centre and nowhere else.
    ///
    /// ```
    /// use mcint::measure::{Lebesgue, UnboundedTransform};
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// assert_eq!(SobolDesign::new(Uniform::unit(4).unwrap()).unwrap().factors(), 4);
    /// let line = Lebesgue::whole_space(1, UnboundedTransform::Rational).unwrap();
    /// let err = SobolDesign::new(line).err().unwrap().to_string();
    /// assert!(err.contains("probability law"), "{err}");
    /// ```
    pub fn new(inputs: M) -> Result<Self> {
        let k = inputs.canonical_dims();
        let mut x = vec![0.0; inputs.dims()];
        let spread: Vec<f64> = (0..k)
            .map(|i| ((i as f64 + 0.5) * 0.618_033_988_749_894_9).fract())
            .collect();
        for (u, at) in [
            (vec![0.5; k], "the centre of the cube"),
            (vec![0.1; k], "(0.1, 0.1, ...)"),
            (spread, "(0.309, 0.927, ...)"),
        ] {
            let weight = inputs.map(&u, &mut x);
            if weight != 1.0 {
                return Err(Error::invalid(
                    "inputs",
                    format!("a measure of weight {weight} at {at}"),
                    "a probability law (weight 1), such as a Uniform or a Gaussian: Sobol' \
                     indices split the variance of the output under the inputs' law",
                ));
            }
        }
        Ok(SobolDesign {
            inputs: Arc::new(inputs),
            factors: Arc::new((0..k).map(|i| vec![i]).collect()),
            second_order: false,
            tolerance: None,
            points: DEFAULT_POINTS,
            replicates: None,
            built: Mutex::new(Vec::new()),
        })
    }

    /// Indices of groups of inputs instead of single inputs: each group is a list of
    /// canonical coordinates, and the groups must be non-empty and disjoint (inputs in no
    /// group still vary, but get no index).
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(4).unwrap()).unwrap();
    /// let grouped = design.groups(vec![vec![0, 1], vec![3]]).unwrap();
    /// assert_eq!(grouped.factors(), 2);
    /// let bad = SobolDesign::new(Uniform::unit(4).unwrap()).unwrap().groups(vec![vec![0], vec![0, 2]]);
    /// assert!(bad.err().unwrap().to_string().contains("disjoint"));
    /// ```
    pub fn groups(mut self, groups: Vec<Vec<usize>>) -> Result<Self> {
        let k = self.inputs.canonical_dims();
        if groups.is_empty() {
            return Err(Error::invalid("groups", "[]", "at least one group"));
        }
        let mut used = vec![false; k];
        for (g, group) in groups.iter().enumerate() {
            if group.is_empty() {
                return Err(Error::invalid(
                    "groups",
                    format!("group {g} is empty"),
                    "non-empty groups of inputs",
                ));
            }
            for &i in group {
                if i >= k {
                    return Err(Error::invalid(
                        "groups",
                        format!("input {i} in group {g}"),
                        format!("inputs 0 to {} of the law's {k} coordinates", k - 1),
                    ));
                }
                if std::mem::replace(&mut used[i], true) {
                    return Err(Error::invalid(
                        "groups",
                        format!("input {i} appears twice"),
                        "disjoint groups: each input in one group at most",
                    ));
                }
            }
        }
        self.factors = Arc::new(groups);
        Ok(self)
    }

    /// Also estimates the second-order indices `S_jk` of every pair of factors (closed
    /// second-order variance minus both first orders, as SALib), at `F` more model runs per
    /// point.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(3).unwrap()).unwrap();
    /// assert_eq!(design.model_runs_per_point(), 5);
    /// assert_eq!(design.second_order(true).model_runs_per_point(), 8);
    /// ```
    pub fn second_order(mut self, on: bool) -> Self {
        self.second_order = on;
        self
    }

    /// Points of the design (each `model_runs_per_point` model runs), split evenly into the
    /// replicates; a power of two keeps each Sobol' net balanced. In a run to a tolerance, the
    /// first stage's points.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().points(1 << 12);
    /// let run = design.integrator(|x: &[f64]| x[0]).unwrap().run().unwrap();
    /// assert_eq!(run.evaluations, 1 << 12);
    /// let odd = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().points(1001);
    /// assert!(odd.integrator(|x: &[f64]| x[0]).is_err());
    /// let three = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().replicates(3);
    /// let error = three.integrator(|x: &[f64]| x[0]).err().unwrap().to_string();
    /// assert!(error.contains("points = 65536 (the default)"), "{error}");
    /// ```
    pub fn points(mut self, points: u64) -> Self {
        self.points = points;
        self
    }

    /// Splits the points into `replicates` independently scrambled sequences: fewer give more
    /// accurate indices and wider intervals (Student-t with `R - 1` degrees of freedom, and a
    /// few-replicates warning below 8); 1 gives one sequence and no error bar. A run to a
    /// tolerance needs at least 2.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().replicates(1);
    /// let run = design.integrator(|x: &[f64]| x[0] * x[1]).unwrap().run().unwrap();
    /// let indices = design.indices(&run).unwrap();
    /// assert!(indices.first_order()[0].std_error.is_none());
    /// assert!((indices.first_order()[0].mean - 3.0 / 7.0).abs() < 1e-4);
    /// ```
    pub fn replicates(mut self, replicates: u64) -> Self {
        self.replicates = Some(replicates);
        self
    }

    /// Runs to a tolerance: the integrator stops when the 95% interval of every index (first
    /// order, total and any second order, of every output) meets `tolerance` (an absolute
    /// one suits indices, which are fractions of 1; a relative one never stops on an index of
    /// zero). Its evaluation limit counts points, each `model_runs_per_point` model runs.
    /// Such a run cannot be checkpointed: its stages depend on its results so far, and
    /// [`run_part`](Integrator::run_part) refuses it.
    ///
    /// ```
    /// use mcint::{Tolerance, measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap())
    ///     .unwrap()
    ///     .tolerance(Tolerance::absolute(1e-3).unwrap());
    /// let run = design.integrator(|x: &[f64]| x[0] + 2.0 * x[1]).unwrap().run().unwrap();
    /// let indices = design.indices(&run).unwrap();
    /// assert_eq!(indices.converged, Some(true));
    /// assert!(indices.total()[1].half_width(0.95).unwrap().unwrap() <= 1e-3);
    /// let part = design.integrator(|x: &[f64]| x[0]).unwrap().run_part(0..1);
    /// assert!(part.unwrap_err().to_string().contains("no tolerance for a run in parts"));
    /// ```
    pub fn tolerance(mut self, tolerance: Tolerance) -> Self {
        self.tolerance = Some(tolerance);
        self
    }

    /// Number of factors `F` (inputs, or groups).
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// assert_eq!(SobolDesign::new(Uniform::unit(5).unwrap()).unwrap().factors(), 5);
    /// ```
    pub fn factors(&self) -> usize {
        self.factors.len()
    }

    /// Model runs per point of the design: `f(A)`, `f(B)`, and `f(AB_j)` (and `f(BA_j)` with
    /// second order) for each factor.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// assert_eq!(SobolDesign::new(Uniform::unit(6).unwrap()).unwrap().model_runs_per_point(), 8);
    /// ```
    pub fn model_runs_per_point(&self) -> u64 {
        let per_factor = if self.second_order { 2 } else { 1 };
        2 + per_factor * self.factors() as u64
    }

    /// Dimensions of the design's points: twice the law's canonical dimension.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// assert_eq!(SobolDesign::new(Uniform::unit(3).unwrap()).unwrap().point_dims(), 6);
    /// ```
    pub fn point_dims(&self) -> usize {
        2 * self.inputs.canonical_dims()
    }

    /// The model's inputs at every run of the design point `point` (in `[0, 1)`, of
    /// [`point_dims`](Self::point_dims) coordinates, such as the canonical point of a
    /// [`NonFiniteContribution`](crate::Error::NonFiniteContribution) error of the design's
    /// run), one run per row: `A` (from the point's first half), `B` (its second half),
    /// `AB_j` in row `2 + j` (`A` with factor `j`'s coordinates from `B`) and, with second
    /// order, `BA_j` in row `2 + F + j`. What tells which model run was not finite.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
    /// let runs = design.model_inputs(&[0.1, 0.2, 0.7, 0.8]).unwrap();
    /// assert_eq!(runs.len(), 4); // A, B, AB_0, AB_1
    /// assert_eq!((runs.column(0)[2], runs.column(1)[2]), (0.7, 0.2)); // AB_0
    /// assert!(design.model_inputs(&[0.5]).is_err());
    /// ```
    pub fn model_inputs(&self, point: &[f64]) -> Result<Points> {
        if point.len() != self.point_dims() || !point.iter().all(|u| (0.0..1.0).contains(u)) {
            return Err(Error::invalid(
                "design point",
                format!("{point:?}"),
                format!("{} coordinates in [0, 1)", self.point_dims()),
            ));
        }
        let layout = Layout::new(self.factors(), 1, self.second_order)?;
        let runs = runs_per_point(layout);
        let mut inputs = Points::new(self.inputs.dims(), runs)?;
        let mut mixed = vec![0.0; self.inputs.canonical_dims()];
        let mut x = vec![0.0; self.inputs.dims()];
        each_run(
            layout,
            &self.factors,
            point,
            &mut mixed,
            |canonical, slot| {
                self.inputs.map(canonical, &mut x);
                for (c, &v) in x.iter().enumerate() {
                    inputs.column_mut(c)[slot] = v;
                }
            },
        );
        Ok(inputs)
    }

    /// The run of a scalar model `f(x)`, ready to be configured further and run. Errors when
    /// the design's integrals do not fit in one vector run, or the points do not split into
    /// the replicates (see [`points`](Self::points), [`replicates`](Self::replicates)). A
    /// non-finite model value stops the run with an error that names the design's output it
    /// reached, as any vector run does.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().points(4096);
    /// let run = design.integrator(|x: &[f64]| x[0] * x[1]).unwrap().threads(2).run().unwrap();
    /// assert_eq!(run.evaluations, 4096); // points; each ran the model 4 times
    /// ```
    pub fn integrator<F>(&self, model: F) -> Result<DesignRun>
    where
        F: Fn(&[f64]) -> f64 + Send + Sync + 'static,
    {
        self.integrator_vector(1, move |x: &[f64], out: &mut [f64]| out[0] = model(x))
    }

    /// The run of a model with `outputs` outputs, `f(x, out)` writing output `o` to
    /// `out[o]`: indices per output, over the same points.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
    /// let model = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = x[1]; };
    /// let run = design.integrator_vector(2, model).unwrap().seed(3).run().unwrap();
    /// let indices = design.indices(&run).unwrap();
    /// assert!((indices.outputs[0].first_order[0].mean - 1.0).abs() < 1e-3);
    /// assert!((indices.outputs[1].first_order[1].mean - 1.0).abs() < 1e-3);
    /// ```
    pub fn integrator_vector<F>(&self, outputs: usize, model: F) -> Result<DesignRun>
    where
        F: Fn(&[f64], &mut [f64]) + Send + Sync + 'static,
    {
        let layout = self.built_layout(outputs)?;
        let integrand: DesignIntegrand = Box::new(pick_freeze(
            Arc::clone(&self.inputs),
            Arc::clone(&self.factors),
            layout,
            model,
        ));
        self.run_of(layout, integrand)
    }

    /// The run of a model evaluated a block of inputs at a time, for models that pay a cost
    /// per call (an interpreter, a GPU kernel): `model(inputs, out)` gets the inputs of every
    /// model run of a block of design points (one column per input of the law) and writes
    /// output `o` of input `i` to `out[o * n + i]`. With the same arithmetic per input, the
    /// run has the bits of [`integrator_vector`](Self::integrator_vector).
    ///
    /// ```
    /// use mcint::{Points, measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().points(4096);
    /// let per_point = |x: &[f64], out: &mut [f64]| out[0] = x[0] + x[0] * x[1];
    /// let block = |x: &Points, out: &mut [f64]| {
    ///     for (i, y) in out.iter_mut().enumerate() {
    ///         *y = x.get(i, 0) + x.get(i, 0) * x.get(i, 1);
    ///     }
    /// };
    /// let a = design.integrator_vector(1, per_point).unwrap().seed(2).run().unwrap();
    /// let b = design.integrator_batch(1, block).unwrap().seed(2).run().unwrap();
    /// assert_eq!(a, b);
    /// ```
    pub fn integrator_batch<F>(&self, outputs: usize, model: F) -> Result<DesignRun>
    where
        F: Fn(&Points, &mut [f64]) + Send + Sync + 'static,
    {
        let layout = self.built_layout(outputs)?;
        let integrand: DesignIntegrand = Box::new(pick_freeze_batch(
            Arc::clone(&self.inputs),
            Arc::clone(&self.factors),
            layout,
            model,
        ));
        self.run_of(layout, integrand)
    }

    /// The Integrator of the design's `integrand`, with its points, replicates and
    /// tolerances.
    fn run_of(&self, layout: Layout, integrand: DesignIntegrand) -> Result<DesignRun> {
        let outputs = layout.model_outputs;
        let dims = self.point_dims();
        let replicates = self.replicates.unwrap_or(DEFAULT_REPLICATES);
        let least = if self.tolerance.is_some() { 2 } else { 1 };
        if replicates < least {
            return Err(Error::invalid(
                "replicates",
                replicates,
                format!(
                    "at least {least} independent scrambles{}",
                    if least == 2 {
                        " in a run to a tolerance (its stopping rule needs an error bar)"
                    } else {
                        ""
                    }
                ),
            ));
        }
        if self.points < replicates || !self.points.is_multiple_of(replicates) {
            // Said of the default too: a caller who set only the replicates meets it here.
            let default = if self.points == DEFAULT_POINTS {
                " (the default)"
            } else {
                ""
            };
            return Err(Error::invalid(
                "points",
                format!("{}{default}", self.points),
                format!(
                    "a positive multiple of the {replicates} replicates: a power of two such as \
                     {DEFAULT_POINTS} keeps each Sobol' net balanced"
                ),
            ));
        }
        let mut integrator =
            Integrator::over_box_vector_batch(layout.outputs(), integrand, UniformBox::unit(dims)?)
                .sampler(Sobol::new(dims, Scramble::Lms, 0)?)
                .samples(self.points / replicates)
                .replicates(replicates);
        if let Some(tolerance) = self.tolerance {
            for o in 0..outputs {
                for j in 0..layout.factors {
                    integrator = integrator
                        .derived_tolerance(layout.first_order(o, j), tolerance)
                        .derived_tolerance(layout.total_order(o, j), tolerance);
                    if layout.second_order {
                        for k in j + 1..layout.factors {
                            integrator = integrator
                                .derived_tolerance(layout.second_order(o, j, k), tolerance);
                        }
                    }
                }
            }
        }
        Ok(integrator)
    }

    /// The indices from a run of [`integrator`](Self::integrator) or
    /// [`integrator_vector`](Self::integrator_vector) of this design.
    ///
    /// Errors when the run does not have the outputs of an integrator this design built (of
    /// any multiple of its outputs per model output, for a design that built none), or when
    /// an output's variance is within rounding of zero (a constant output has no variance to
    /// split).
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
    /// let run = design.integrator(|_: &[f64]| 1.0).unwrap().run().unwrap();
    /// let err = design.indices(&run).unwrap_err().to_string();
    /// assert!(err.contains("variance"), "{err}");
    /// ```
    pub fn indices(&self, run: &VectorEstimate) -> Result<Indices> {
        let layout = self.layout_of(run)?;
        // Less its value at the centre, a constant model is exactly 0: refused as constant
        // here, before its standard errors' rounding floor reads as a model too small.
        for o in 0..layout.model_outputs {
            let start = layout.moments(o);
            if run.outputs[start..start + 4].iter().all(|e| e.mean == 0.0) {
                return Err(constant_output(o, 0.0, 0.0));
            }
        }
        // The model's values and squares (the first four integrals of each output's block)
        // are not all zero: a standard error too small for the error bars is a model too small.
        let moments = (0..layout.model_outputs).flat_map(|o| (0..4).map(move |k| (o, k)));
        for (o, k) in moments {
            if unrepresentable_output(run, [layout.moments(o) + k]).is_some() {
                return Err(too_small(layout, run, o));
            }
        }
        let outputs = (0..layout.model_outputs)
            .map(|o| self.output_indices(layout, run, o))
            .collect::<Result<Vec<_>>>()?;
        let mut warnings: Vec<Warning> = Vec::new();
        for warning in run.outputs.iter().flat_map(|e| &e.warnings) {
            if !warnings.contains(warning) {
                warnings.push(warning.clone());
            }
        }
        Ok(Indices {
            outputs,
            factors: self.factors.to_vec(),
            points: run.evaluations,
            model_evaluations: run.evaluations.saturating_mul(self.model_runs_per_point()),
            stop: run.stop,
            converged: run.converged,
            warnings,
        })
    }

    /// The layout of an integrator for `outputs` model outputs, remembered for
    /// [`indices`](Self::indices).
    fn built_layout(&self, outputs: usize) -> Result<Layout> {
        let layout = self.layout(outputs)?;
        let mut built = self.built.lock().unwrap_or_else(|e| e.into_inner());
        if !built.contains(&outputs) {
            built.push(outputs);
        }
        Ok(layout)
    }

    fn layout(&self, outputs: usize) -> Result<Layout> {
        Layout::new(self.factors(), outputs, self.second_order)
    }

    /// The layout of `run`, or an error when it is not a run of this design: its outputs
    /// must be those of an integrator the design built (or, for a design that built none, as
    /// for a run read back from a file, a multiple of the outputs per model output).
    fn layout_of(&self, run: &VectorEstimate) -> Result<Layout> {
        let block = self.layout(1)?.block();
        let outputs = run.outputs.len();
        let built = self.built.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let fits = if built.is_empty() {
            outputs > 0 && outputs.is_multiple_of(block)
        } else {
            built.iter().any(|&m| m * block == outputs)
        };
        if !fits {
            let counts = if built.is_empty() {
                format!("a multiple of {block}")
            } else {
                let counts: Vec<String> = built.iter().map(|m| (m * block).to_string()).collect();
                counts.join(" or ")
            };
            let second = if self.second_order {
                " with second order"
            } else {
                ""
            };
            return Err(Error::invalid(
                "run",
                format!("a run of {outputs} outputs"),
                format!(
                    "a run of this design: {counts} outputs, as its integrators give ({block} \
                     per model output for its {} factors{second})",
                    self.factors()
                ),
            ));
        }
        self.layout(outputs / block)
    }

    fn output_indices(
        &self,
        layout: Layout,
        run: &VectorEstimate,
        o: usize,
    ) -> Result<OutputIndices> {
        let variance = run.derived(&layout.variance(o))?;
        // `E f^2 - (E f)^2` from means of `n` values: each mean's rounding error is at most
        // about `n` ulps of the mean of squares (sums of `n` terms), so a variance within a
        // few times that of zero is rounding, not variance.
        let moments = layout.moments(o);
        let squares = 0.5 * (run.outputs[moments + 2].mean + run.outputs[moments + 3].mean);
        let rounding = 4.0 * f64::EPSILON * run.evaluations as f64 * squares;
        if variance.mean.is_nan() || variance.mean <= rounding {
            return Err(constant_output(o, variance.mean, rounding));
        }
        let per_factor = |index: &dyn Fn(usize) -> crate::stats::Derived| {
            (0..layout.factors)
                .map(|j| run.derived(&index(j)))
                .collect::<Result<Vec<_>>>()
        };
        let mut second_order = Vec::new();
        if layout.second_order {
            for j in 0..layout.factors {
                for k in j + 1..layout.factors {
                    second_order.push(SecondOrder {
                        factors: (j, k),
                        index: run.derived(&layout.second_order(o, j, k))?,
                    });
                }
            }
        }
        Ok(OutputIndices {
            first_order: per_factor(&|j| layout.first_order(o, j))?,
            total: per_factor(&|j| layout.total_order(o, j))?,
            second_order,
            variance,
        })
    }
}

/// The error for model output `o`, whose `variance` is within `rounding` of zero.
fn constant_output(o: usize, variance: f64, rounding: f64) -> Error {
    Error::invalid(
        "model output",
        if rounding > 0.0 {
            format!(
                "output {o} with variance {variance:.1e}, within rounding ({rounding:.1e}) of 0"
            )
        } else {
            format!("output {o} with variance {variance:.1e}")
        },
        "an output with positive variance: a constant output has no variance to split among \
         its inputs",
    )
}

/// The error for model output `o`, whose values are so small that the design's squares of
/// them have variances f64 cannot hold (their indices' error bars came out 1e-9 of the true
/// ones near `1e-80`, and could not be formed at all below).
fn too_small(layout: Layout, run: &VectorEstimate, o: usize) -> Error {
    let moments = layout.moments(o);
    let mean = |k: usize| run.outputs[moments + k].mean.abs();
    let magnitude = mean(2).max(mean(3)).sqrt().max(mean(0)).max(mean(1));
    // A power of two near 1 / magnitude, at most 2^1000: past 2^1023 it would print as inf,
    // and 2^1000 brings even the least subnormal to about 1e-23. (A magnitude of 0 is a
    // constant model, refused as such before.)
    let factor = if magnitude > 0.0 {
        2f64.powi((-(magnitude.log2().round() as i32)).min(1000))
    } else {
        1.0
    };
    Error::invalid(
        "model output",
        format!("output {o} of magnitude about {magnitude:.1e}"),
        format!(
            "outputs from about 1e-70 up: the design squares the model's values, and the \
             indices' error bars square those again; multiply the model by a constant such as \
             {factor:.0e} (its indices do not change)"
        ),
    )
}

/// The design's integrand over `[0,1)^{2k}` (the table of the `layout` module), on blocks
/// of points: the buffers are allocated once per block, not per point.
fn pick_freeze<M: Measure, F: Fn(&[f64], &mut [f64]) + Send + Sync>(
    inputs: Arc<M>,
    factors: Arc<Vec<Vec<usize>>>,
    layout: Layout,
    model: F,
) -> impl Fn(&Points, &mut [f64]) + Send + Sync {
    let shift = OnceLock::new();
    move |points: &Points, out: &mut [f64]| {
        let n = points.len();
        let m = layout.model_outputs;
        let mut u = vec![0.0; 2 * inputs.canonical_dims()];
        let mut mixed = vec![0.0; inputs.canonical_dims()];
        let mut x = vec![0.0; inputs.dims()];
        let shift = shift.get_or_init(|| shifts(&*inputs, m, |x, probe| model(x, probe)));
        let mut values = vec![0.0; m * runs_per_point(layout)];
        let mut row = vec![0.0; layout.outputs()];
        for i in 0..n {
            points.copy_point(i, &mut u);
            each_run(layout, &factors, &u, &mut mixed, |canonical, slot| {
                inputs.map(canonical, &mut x);
                model(&x, &mut values[slot * m..(slot + 1) * m]);
            });
            integrals(layout, &values, shift, &mut row);
            for (k, value) in row.iter().enumerate() {
                out[k * n + i] = *value;
            }
        }
    }
}

/// [`pick_freeze`] for a model that takes blocks: the inputs of every run of the block's
/// points (slot by slot: run `slot` of point `i` is input `slot * n + i`) in one call.
fn pick_freeze_batch<M: Measure, F: Fn(&Points, &mut [f64]) + Send + Sync>(
    inputs: Arc<M>,
    factors: Arc<Vec<Vec<usize>>>,
    layout: Layout,
    model: F,
) -> impl Fn(&Points, &mut [f64]) + Send + Sync {
    let shift = OnceLock::new();
    move |points: &Points, out: &mut [f64]| {
        let n = points.len();
        let (m, slots, d) = (layout.model_outputs, runs_per_point(layout), inputs.dims());
        let shift = shift.get_or_init(|| {
            shifts(&*inputs, m, |x, probe| {
                if let Ok(mut centre) = Points::new(d, 1) {
                    for (c, &v) in x.iter().enumerate() {
                        centre.column_mut(c)[0] = v;
                    }
                    model(&centre, probe);
                }
            })
        });
        // Bounded by the block and the design's size; refused, the block is non-finite and
        // the run says so.
        let Ok(mut runs) = Points::new(d, n * slots) else {
            out.fill(f64::NAN);
            return;
        };
        let mut u = vec![0.0; 2 * inputs.canonical_dims()];
        let mut mixed = vec![0.0; inputs.canonical_dims()];
        let mut x = vec![0.0; d];
        for i in 0..n {
            points.copy_point(i, &mut u);
            each_run(layout, &factors, &u, &mut mixed, |canonical, slot| {
                inputs.map(canonical, &mut x);
                for (c, &v) in x.iter().enumerate() {
                    runs.column_mut(c)[slot * n + i] = v;
                }
            });
        }
        // An output the model does not write is non-finite.
        let mut values = vec![f64::NAN; m * n * slots];
        model(&runs, &mut values);
        let mut point = vec![0.0; m * slots];
        let mut row = vec![0.0; layout.outputs()];
        for i in 0..n {
            for slot in 0..slots {
                for o in 0..m {
                    point[slot * m + o] = values[o * n * slots + slot * n + i];
                }
            }
            integrals(layout, &point, shift, &mut row);
            for (k, value) in row.iter().enumerate() {
                out[k * n + i] = *value;
            }
        }
    }
}

/// Model runs per design point: `A`, `B`, every `AB_j`, and with second order every `BA_j`.
fn runs_per_point(layout: Layout) -> usize {
    let mixed = if layout.second_order {
        2 * layout.factors
    } else {
        layout.factors
    };
    2 + mixed
}

/// Calls `run(canonical input, slot)` for every model run of the design point `u` (`A`
/// from its first half, `B` from its second): `A` in slot 0, `B` in 1, `AB_j` in `2 + j`,
/// `BA_j` in `2 + F + j`. `mixed` is scratch of the law's canonical dimension.
fn each_run(
    layout: Layout,
    factors: &[Vec<usize>],
    u: &[f64],
    mixed: &mut [f64],
    mut run: impl FnMut(&[f64], usize),
) {
    let nf = layout.factors;
    let (a, b) = u.split_at(mixed.len());
    run(a, 0);
    run(b, 1);
    mixed.copy_from_slice(a);
    for (j, factor) in factors.iter().enumerate() {
        factor.iter().for_each(|&c| mixed[c] = b[c]);
        run(mixed, 2 + j);
        factor.iter().for_each(|&c| mixed[c] = a[c]);
    }
    if layout.second_order {
        mixed.copy_from_slice(b);
        for (j, factor) in factors.iter().enumerate() {
            factor.iter().for_each(|&c| mixed[c] = a[c]);
            run(mixed, 2 + nf + j);
            factor.iter().for_each(|&c| mixed[c] = b[c]);
        }
    }
}

/// The largest shift: the error bars take fourth powers of the shifted values, which a
/// spike of the model at the centre (`1 / (x^2 + 1e-100)`) would overflow.
const LARGEST_SHIFT: f64 = 3e38;

/// The shift of each of the `m` model outputs: its value (by `model_at`) at the point the
/// centre of the law's cube maps to, or 0 where that is not finite or beyond
/// [`LARGEST_SHIFT`] (a model may be singular or spike there and be moderate everywhere
/// else).
fn shifts<M: Measure>(inputs: &M, m: usize, model_at: impl FnOnce(&[f64], &mut [f64])) -> Vec<f64> {
    let mut x = vec![0.0; inputs.dims()];
    inputs.map(&vec![0.5; inputs.canonical_dims()], &mut x);
    let mut probe = vec![f64::NAN; m];
    model_at(&x, &mut probe);
    probe
        .iter_mut()
        .filter(|v| v.is_nan() || v.abs() > LARGEST_SHIFT)
        .for_each(|v| *v = 0.0);
    probe
}

/// One point's integrands from its model values (`values[slot * m + o]`, slots as in
/// [`pick_freeze`]), each less its output's `shift`.
///
/// The shift is a constant taken from the model itself (its value at one fixed point), so
/// the estimators stay valid: Jansen's total and the variance do not change with it, and the
/// first and second order numerators keep their expectations (`E[f(AB_j) - f(A)] = 0`). It
/// takes off the model's mean, which would otherwise cancel in `E f^2 - (E f)^2`: the
/// variance of `1e8 + x` came out 0, and a constant model got a variance of rounding noise.
fn integrals(layout: Layout, values: &[f64], shift: &[f64], row: &mut [f64]) {
    let (m, nf) = (layout.model_outputs, layout.factors);
    for o in 0..m {
        let value = |slot: usize| values[slot * m + o] - shift[o];
        let (fa, fb) = (value(0), value(1));
        let start = layout.moments(o);
        row[start..start + 4].copy_from_slice(&[fa, fb, fa * fa, fb * fb]);
        for j in 0..nf {
            let fab = value(2 + j);
            row[layout.first(o, j)] = fb * (fab - fa);
            row[layout.total(o, j)] = 0.5 * (fa - fab) * (fa - fab);
            if layout.second_order {
                let fba = value(2 + nf + j);
                for k in j + 1..nf {
                    row[layout.pair(o, j, k)] = fba * value(2 + k) - fa * fb;
                }
            }
        }
    }
}
