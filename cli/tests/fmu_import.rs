//! The FMUs of `hysteron export-fmu`, FMI 2.0 and FMI 3.0, imported by a
//! second FMI host beside FMPy (capi/checks): the Rust `fmi` crate, which
//! unpacks the archive, parses `modelDescription.xml` with its own schema,
//! loads the binary and calls the FMI functions. For the paper model and
//! the Bouc-Wen benchmark system, each FMU is instantiated for
//! co-simulation, given a changed parameter, driven over a few hundred
//! steps of an input that reverses many times, and compared with `hysteron
//! simulate` of the spec with that parameter changed; then reset and run
//! again, which gives the first run's outputs bit for bit.
//!
//! The binary packed into the FMU is the `libhysteron_c.so` cargo built
//! with the `hysteron` program of this test (see [`library`]).

mod common;

use common::hysteron;
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation as _, Common as _, InstanceCS as Fmi2Instance};
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::instance::InstanceCS as Fmi3Instance;
use fmi::fmi3::{CoSimulation as _, Fmi3Model as _, GetSet as _};
use fmi::schema::traits::FmiModelDescription;
use fmi::traits::{FmiImport, FmiInstance};
use hysteron_cli::csvio::read_columns;
use std::collections::HashMap;
use std::fmt::Debug;
use std::path::{Path, PathBuf};

/// The communication step: a power of two, so that every communication
/// point `k · H` is exact and the steps the FMU sees are exactly `H`.
const H: f64 = 1.0 / 1024.0;

/// Steps of each run.
const STEPS: usize = 600;

/// The relative tolerance on the outputs against `hysteron simulate`.
const RTOL: f64 = 1e-12;

/// A model, the parameter changed through FMI, and the input it is driven
/// with.
struct Case {
    /// The spec under `examples/specs`.
    spec: &'static str,
    /// The parameter's FMI variable name.
    parameter: &'static str,
    /// The same parameter in the spec (a JSON pointer).
    pointer: &'static str,
    /// Its changed value.
    value: f64,
    /// The input, `STEPS` samples.
    input: fn() -> Vec<f64>,
}

/// The paper's model (friction in a gap, Bouc-Wen spring): its Coulomb
/// force changed, driven by a decaying sine with a faster ripple (minor
/// loops inside major ones).
const PAPER: Case = Case {
    spec: "paper.json",
    parameter: "left.mms.f_c",
    pointer: "/left/f_c",
    value: 2.5,
    input: decaying_sine,
};

/// The Bouc-Wen benchmark system (a mass-spring-damper with a Bouc-Wen
/// spring in its feedback path, rate-dependent, its period the
/// communication step): its Bouc-Wen `beta` changed, driven by the
/// benchmark's validation multisine (the force, in N).
const BOUC_WEN: Case = Case {
    spec: "boucwen-benchmark.json",
    parameter: "inner.feedback.back.bouc_wen.beta",
    pointer: "/inner/back/beta",
    value: 1600.0,
    input: multisine,
};

fn decaying_sine() -> Vec<f64> {
    let n = STEPS as f64;
    (0..STEPS)
        .map(|i| {
            let i = i as f64;
            let tau = std::f64::consts::TAU;
            1.4 * (-i / n).exp() * (tau * i / 200.0).sin() + 0.14 * (tau * i / 37.0).sin()
        })
        .collect()
}

fn multisine() -> Vec<f64> {
    let path = root().join("data/boucwen-benchmark/val_multisine.csv");
    let columns = read_columns(&path, &["u"]).expect("val_multisine.csv");
    columns.values[0][..STEPS].to_vec()
}

/// The workspace's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The FMU binary: the `libhysteron_c.so` that cargo built for this test,
/// as part of the CLI's dependency `hysteron-c` (a cdylib and an rlib:
/// cargo builds both of a dependency's crate types, into `deps/` beside
/// the program), so it is always the C side of the program under test.
fn library() -> PathBuf {
    let cli = Path::new(env!("CARGO_BIN_EXE_hysteron"));
    let library = cli.with_file_name("deps").join("libhysteron_c.so");
    assert!(
        library.is_file(),
        "{} is missing: cargo builds it with the hysteron-c crate",
        library.display()
    );
    library
}

/// `hysteron export-fmu` of `spec` as FMI `version` ("2" or "3").
fn export(spec: &Path, version: &str, out: &Path) -> PathBuf {
    let fmu = out.join(format!("model{version}.fmu"));
    hysteron(out)
        .args(["export-fmu", "--fmi", version, "--model"])
        .arg(spec)
        .arg("--output")
        .arg(&fmu)
        .arg("--library")
        .arg(library())
        .assert()
        .success();
    fmu
}

/// `hysteron simulate` of `spec` over `x` at the period `H`: the output.
fn simulate(spec: &Path, x: &[f64], out: &Path) -> Vec<f64> {
    let input = out.join("in.csv");
    let output = out.join("out.csv");
    let text: String = x.iter().map(|v| format!("{v:?}\n")).collect();
    std::fs::write(&input, format!("x\n{text}")).unwrap();
    hysteron(out)
        .args(["simulate", "--dt", &format!("{H:?}"), "--model"])
        .arg(spec)
        .arg("--input")
        .arg(&input)
        .arg("--output")
        .arg(&output)
        .assert()
        .success();
    read_columns(&output, &["y"])
        .expect("simulate's output")
        .values
        .remove(0)
}

/// The calls whose form differs between the versions: values and steps.
trait Calls {
    fn set(&mut self, vr: u32, value: f64);
    fn get(&mut self, vr: u32) -> f64;
    /// One communication step from `t` to `t + H`.
    fn step(&mut self, t: f64);
}

/// A co-simulation instance of either version, as the test drives it.
trait Slave: Calls {
    /// Initialization at time 0, after which it steps.
    fn initialize(&mut self);
    /// Back to the state just after instantiation.
    fn reset(&mut self);
}

/// The calls both versions share.
impl<I: Calls + FmiInstance> Slave for I {
    fn initialize(&mut self) {
        self.enter_initialization_mode(None, 0.0, None)
            .expect("enter initialization mode");
        self.exit_initialization_mode()
            .expect("exit initialization mode");
    }

    fn reset(&mut self) {
        FmiInstance::reset(self).expect("reset");
    }
}

/// [`Calls::set`] and [`Calls::get`] through the fmi crate's setter and
/// getter of one value type (they differ only in name between versions).
macro_rules! set_and_get {
    ($set:ident, $get:ident) => {
        fn set(&mut self, vr: u32, value: f64) {
            self.$set(&[vr], &[value]).expect(stringify!($set));
        }

        fn get(&mut self, vr: u32) -> f64 {
            let mut value = [f64::NAN];
            self.$get(&[vr], &mut value).expect(stringify!($get));
            value[0]
        }
    };
}

impl Calls for Fmi2Instance {
    set_and_get!(set_real, get_real);

    fn step(&mut self, t: f64) {
        self.do_step(t, H, true).expect("fmi2DoStep");
    }
}

impl Calls for Fmi3Instance {
    set_and_get!(set_float64, get_float64);

    fn step(&mut self, t: f64) {
        let (mut event, mut terminate, mut early) = (true, true, true);
        let mut last = f64::NAN;
        self.do_step(
            t,
            H,
            true,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
        .expect("fmi3DoStep");
        assert!(!event && !terminate && !early, "fmi3DoStep's flags");
        assert_eq!(last, t + H, "fmi3DoStep's lastSuccessfulTime");
    }
}

/// An FMU as the importer read it: the variables of its description
/// (value reference and causality by name) and an instance. The instance
/// is dropped before the import, whose directory holds the binary.
struct Imported {
    slave: Box<dyn Slave>,
    variables: HashMap<String, (u32, String)>,
    version: String,
    _import: Box<dyn std::any::Any>,
}

impl Imported {
    /// An instance of `import` (co-simulation: instantiating fails if the
    /// FMU has none) and the variables of its description.
    fn new<M: FmiImport + 'static>(
        import: M,
        variables: HashMap<String, (u32, String)>,
        slave: impl Slave + 'static,
    ) -> Self {
        let version = import.model_description().version_string().to_string();
        Imported {
            slave: Box::new(slave),
            variables,
            version,
            _import: Box::new(import),
        }
    }

    fn vr(&self, name: &str) -> u32 {
        self.variables
            .get(name)
            .unwrap_or_else(|| panic!("no variable `{name}`"))
            .0
    }

    fn causality(&self, name: &str) -> &str {
        &self.variables[name].1
    }
}

/// A variable as [`Imported`] keeps it.
fn variable(name: &str, vr: u32, causality: impl Debug) -> (String, (u32, String)) {
    (name.to_string(), (vr, format!("{causality:?}")))
}

fn import2(fmu: &Path) -> Imported {
    let import: Fmi2Import = fmi::import::from_path(fmu).expect("FMI 2.0 import");
    let variables = import.model_description().model_variables.variables.iter();
    let variables = variables
        .map(|v| variable(&v.name, v.value_reference, &v.causality))
        .collect();
    let slave = import.instantiate_cs("importer", false, true);
    Imported::new(import, variables, slave.expect("fmi2Instantiate"))
}

fn import3(fmu: &Path) -> Imported {
    let import: Fmi3Import = fmi::import::from_path(fmu).expect("FMI 3.0 import");
    let variables = import.model_description().model_variables.iter_abstract();
    let variables = variables
        .map(|v| variable(v.name(), v.value_reference(), v.causality()))
        .collect();
    let slave = import.instantiate_cs("importer", false, true, false, false, &[]);
    Imported::new(
        import,
        variables,
        slave.expect("fmi3InstantiateCoSimulation"),
    )
}

/// Sets the changed parameter, initializes and runs `x`: the outputs.
fn run(fmu: &mut Imported, case: &Case, x: &[f64]) -> Vec<f64> {
    let (input, output, parameter) = (fmu.vr("x"), fmu.vr("y"), fmu.vr(case.parameter));
    fmu.slave.set(parameter, case.value);
    assert_eq!(fmu.slave.get(parameter), case.value);
    fmu.slave.initialize();
    x.iter()
        .enumerate()
        .map(|(k, &v)| {
            fmu.slave.set(input, v);
            fmu.slave.step(k as f64 * H);
            fmu.slave.get(output)
        })
        .collect()
}

/// The largest error of `got` relative to `want`, sample by sample.
fn max_relative_error(got: &[f64], want: &[f64]) -> f64 {
    assert_eq!(got.len(), want.len());
    got.iter()
        .zip(want)
        .map(|(g, w)| {
            let e = (g - w).abs();
            if e == 0.0 {
                0.0
            } else {
                e / w.abs()
            }
        })
        .fold(0.0, f64::max)
}

/// The whole check of `case` as FMI `version`, imported by `import`.
fn check(case: &Case, version: &str, import: fn(&Path) -> Imported) {
    let dir = tempfile::tempdir().unwrap();
    let spec = root().join("examples/specs").join(case.spec);
    let fmu_path = export(&spec, version, dir.path());
    let mut fmu = import(&fmu_path);
    assert_eq!(fmu.version, format!("{version}.0"));
    assert_eq!(fmu.causality("x"), "Input");
    assert_eq!(fmu.causality("y"), "Output");
    assert_eq!(fmu.causality(case.parameter), "Parameter");

    // The spec with the parameter changed, as the CLI runs it.
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&spec).unwrap()).unwrap();
    let default = json.pointer(case.pointer).and_then(|v| v.as_f64());
    assert!(
        default.is_some_and(|d| d != case.value),
        "{}: {} is {default:?}",
        case.spec,
        case.pointer
    );
    *json.pointer_mut(case.pointer).unwrap() = case.value.into();
    let changed = dir.path().join("changed.json");
    std::fs::write(&changed, json.to_string()).unwrap();

    let x = (case.input)();
    let reversals = x
        .windows(3)
        .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0)
        .count();
    assert!(reversals >= 10, "{}: {reversals} reversals", case.spec);
    let want = simulate(&changed, &x, dir.path());
    let unchanged = simulate(&spec, &x, dir.path());

    let first = run(&mut fmu, case, &x);
    let error = max_relative_error(&first, &want);
    assert!(
        error <= RTOL,
        "{} FMI {version}: relative error {error:e}",
        case.spec
    );
    // The parameter took effect: the run is far from the unchanged spec's.
    let away = max_relative_error(&first, &unchanged);
    assert!(
        away > 1e-3,
        "{} FMI {version}: {away:e} from the unchanged spec",
        case.spec
    );

    // Reset: the parameter is back at the spec's value until set again,
    // and the run repeats bit for bit.
    fmu.slave.reset();
    let vr = fmu.vr(case.parameter);
    assert_eq!(Some(fmu.slave.get(vr)), default);
    let again = run(&mut fmu, case, &x);
    assert!(
        again
            .iter()
            .zip(&first)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "{} FMI {version}: the run after reset differs",
        case.spec
    );
}

#[test]
fn fmi2_fmus_of_the_paper_model_and_the_benchmark_match_the_cli() {
    for case in [&PAPER, &BOUC_WEN] {
        check(case, "2", import2);
    }
}

#[test]
fn fmi3_fmus_of_the_paper_model_and_the_benchmark_match_the_cli() {
    for case in [&PAPER, &BOUC_WEN] {
        check(case, "3", import3);
    }
}
