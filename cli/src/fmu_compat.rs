//! `hysteron fmu-compat OUT_DIR [--fmi 2|3]`: the compatibility
//! information of the FMU export, as FMI tools publish it since the FMI
//! Cross-Check: per model and FMI version, the FMU, an input
//! (`<Model>_in.csv`), the reference output computed by the hysteron
//! library (`<Model>_ref.csv`), the settings that reproduce it
//! (`<Model>_ref.opt`) and a `ReadMe.md`.
//!
//! The models are the paper's (`examples/specs/paper.json`) and the Bouc-Wen
//! benchmark system (`examples/specs/boucwen-benchmark.json`), built into
//! the program. Each goes into
//! `OUT_DIR/fmus/<FMI version>/cs/<platform>/hysteron/<version>/<Model>/`,
//! the layout of the cross-check rules (platform `linux64` for FMI 2.0;
//! FMI 3.0 names it by its platform tuple, `x86_64-linux`, as its
//! binaries folder does).
//!
//! The files follow the rules' CSV conventions: the first column is
//! `time`, the header names are the model description's variable names in
//! double quotes, numbers are C floating-point literals (written so that
//! they parse back to the same `f64`), and `_ref.opt` holds `StartTime`,
//! `StopTime`, `StepSize` and `RelTol`. The input has a row at every
//! communication point, so an importer that interpolates it linearly and
//! one that holds it read the same samples. `_ref.opt` has one step size,
//! so the communication step is constant.
//!
//! The reference is the library's, not the FMU's: the spec is built with
//! its sample period set to the step (for the rate-dependent benchmark)
//! and run over the input. An FMI importer sets the input at each
//! communication point `t_k` and then calls `DoStep(t_k, h)`, which takes
//! that input as the sample at `t_k + h` (see
//! [`export_fmu`]); so the reference's row at `t_0` is
//! the output at input 0 in the initial state (the FMU's output after
//! initialization) and its row at `t_{k+1}` is the output after the sample
//! `x(t_k)`.

use crate::csvio::{self, CsvIoError};
use crate::export_fmu::{self, ExportFmuError, ExportFmuOptions, FmiVersion, FmuBinary};
use crate::models::Spec;
use crate::Operator;
use std::fmt::{self, Write as _};
use std::path::{Path, PathBuf};

/// The tool name in the folder layout and the ReadMe.
pub const TOOL: &str = "hysteron";

/// The relative tolerance `_ref.opt` gives: the FMU has no solver, so this
/// is the tolerance an importer's output is expected to meet (FMPy's
/// output is the reference bit for bit).
pub const REL_TOL: f64 = 1e-12;

/// Write the compatibility information of the FMU export into a
/// folder, in the FMI Cross-Check layout
/// (`fmus/<2.0|3.0>/cs/<platform>/hysteron/<version>/<Model>/`): for
/// the paper model and the Bouc-Wen benchmark, per FMI version, the
/// FMU, `<Model>_in.csv`, `<Model>_ref.csv` (computed by the library),
/// `<Model>_ref.opt` and a `ReadMe.md`.
#[derive(Debug, Clone, clap::Args)]
pub struct FmuCompatOptions {
    /// The folder to write into (created if missing); the files go under
    /// its `fmus/` folder, overwriting earlier ones of the same names.
    #[arg(value_name = "OUT_DIR")]
    pub dir: PathBuf,
    /// Only this FMI version: 2 (FMI 2.0) or 3 (FMI 3.0); default both.
    #[arg(long, value_name = "VERSION", value_parser = ["2", "3"])]
    pub fmi: Option<String>,
    /// The FMU binary.
    #[command(flatten)]
    pub binary: FmuBinary,
}

/// A model of the compatibility information.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// The model name: the FMU's file name and model identifier.
    pub name: &'static str,
    /// The spec (JSON).
    pub spec: &'static str,
    /// Where the spec is in the source tree.
    pub spec_path: &'static str,
    /// What the model is (Markdown, for the ReadMe).
    pub about: &'static str,
    /// What the input is (Markdown, for the ReadMe).
    pub input_about: &'static str,
    /// The communication step (s).
    pub step: f64,
    /// The number of steps.
    pub steps: usize,
    /// The input at time `t`.
    pub input: fn(f64) -> f64,
}

impl Case {
    /// The stop time: `steps` steps from 0.
    pub fn stop(&self) -> f64 {
        self.steps as f64 * self.step
    }

    /// The communication points `t_k = k h`, `k = 0..=steps`.
    pub fn times(&self) -> Vec<f64> {
        (0..=self.steps).map(|k| k as f64 * self.step).collect()
    }
}

fn paper_input(t: f64) -> f64 {
    use std::f64::consts::TAU;
    (1.4 - 0.6 * t) * (TAU * 2.0 * t).sin() + 0.12 * (TAU * 21.0 * t).sin()
}

fn benchmark_input(t: f64) -> f64 {
    use std::f64::consts::TAU;
    30.0 * (TAU * 4.0 * t).sin() + 12.0 * (TAU * 17.0 * t).sin() + 5.0 * (TAU * 43.0 * t).sin()
}

/// The models written: the paper's and the Bouc-Wen benchmark system.
pub const CASES: [Case; 2] = [
    Case {
        name: "PaperModel",
        spec: include_str!("../../examples/specs/paper.json"),
        spec_path: "examples/specs/paper.json",
        about: "The hysteresis model of Ruderman & Bertram (2015) as a hysteron spec: \
                a Maxwell-slip friction element (`mms`, Coulomb force `f_c`, stiffness `k`) \
                in mechanical series with a Bouc-Wen spring of tabulated stiffness, the \
                slider's travel held in a gap of width `b` (`limits`). Input `x`: the \
                displacement; output `y`: the force. Rate-independent: its output does not \
                depend on the step size.",
        input_about: "`x(t) = (1.4 − 0.6 t) sin(2π·2 t) + 0.12 sin(2π·21 t)`: two decaying \
                      major cycles, with the 21 Hz part reversing the motion near their \
                      peaks (minor loops).",
        step: 1e-3,
        steps: 1000,
        input: paper_input,
    },
    Case {
        name: "BoucWenBenchmark",
        spec: include_str!("../../examples/specs/boucwen-benchmark.json"),
        spec_path: "examples/specs/boucwen-benchmark.json",
        about: "The Bouc-Wen hysteretic benchmark system of Noël & Schoukens (2016), \
                `m ÿ + c ẏ + k y + z(y, ẏ) = u`: a mass-spring-damper (Newmark average \
                acceleration) with a Bouc-Wen force `z` in its feedback loop, solved at \
                every sub-step, 20 sub-steps per communication step with the input linear \
                in between (`oversample`). Input `x`: the force `u` (N); output `y`: the \
                displacement (m). Rate-dependent: its sample period is the communication \
                step size (the benchmark's 750 Hz here), so the reference holds for this \
                step only.",
        input_about: "`u(t) = 30 sin(2π·4 t) + 12 sin(2π·17 t) + 5 sin(2π·43 t)` N: a \
                      multisine whose higher components reverse the motion within each \
                      4 Hz cycle.",
        step: 1.0 / 750.0,
        steps: 1000,
        input: benchmark_input,
    },
];

/// Why the compatibility information could not be written.
#[derive(Debug, thiserror::Error)]
pub enum FmuCompatError {
    /// The output folder (or one under it) could not be created.
    #[error("cannot create the folder `{}`: {source}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A built-in spec did not build or run (a bug).
    #[error("the reference of {model}: {message}")]
    Reference {
        /// The model.
        model: &'static str,
        /// What went wrong.
        message: String,
    },
    /// Writing an FMU.
    #[error(transparent)]
    Export(#[from] ExportFmuError),
    /// Writing a file.
    #[error(transparent)]
    Write(#[from] CsvIoError),
}

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct FmuCompatReport {
    /// The `fmus` folder.
    pub root: PathBuf,
    /// Each model's folder, relative to `root`.
    pub folders: Vec<PathBuf>,
}

impl fmt::Display for FmuCompatReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "wrote {} FMUs with their input, reference, options and ReadMe under {}:",
            self.folders.len(),
            self.root.display()
        )?;
        for folder in &self.folders {
            write!(f, "\n  {}", folder.display())?;
        }
        Ok(())
    }
}

/// The reference output at the times of `inputs` (see the module docs):
/// the initial output, then the output after each sample but the last
/// (as many values as inputs).
pub fn reference(case: &Case, inputs: &[f64]) -> Result<Vec<f64>, FmuCompatError> {
    let fail = |message: String| FmuCompatError::Reference {
        model: case.name,
        message,
    };
    let spec = Spec::from_json(case.spec).map_err(|e| fail(e.to_string()))?;
    let mut op = spec
        .with_dt(case.step)
        .build()
        .map_err(|e| fail(e.to_string()))?;
    let initial = op.trial(0.0).map_err(|e| fail(e.to_string()))?.output;
    op.reset();
    let mut out = vec![initial];
    let stepped = &inputs[..inputs.len().saturating_sub(1)];
    out.extend(op.run(stepped).map_err(|e| fail(e.to_string()))?);
    out.truncate(inputs.len());
    Ok(out)
}

/// A CSV file of the rules: `time` and one named column, a row per time.
fn csv_text(name: &str, times: &[f64], values: &[f64]) -> String {
    let mut text = format!("\"time\",\"{name}\"\n");
    for (&t, &v) in times.iter().zip(values) {
        csvio::push_f64(&mut text, t);
        text.push(',');
        csvio::push_f64(&mut text, v);
        text.push('\n');
    }
    text
}

/// The `_ref.opt` file.
fn ref_opt(case: &Case) -> String {
    [
        ("StartTime", 0.0),
        ("StopTime", case.stop()),
        ("StepSize", case.step),
        ("RelTol", REL_TOL),
    ]
    .iter()
    .map(|(key, v)| format!("{key}, {}\n", csvio::fmt_f64(*v)))
    .collect()
}

/// The `ReadMe.md` of a model's folder.
fn readme(case: &Case, fmi: FmiVersion) -> String {
    let (name, version) = (case.name, env!("CARGO_PKG_VERSION"));
    let (start, stop, step) = ("0", csvio::fmt_f64(case.stop()), csvio::fmt_f64(case.step));
    let mut s = String::new();
    // Writing to a String cannot fail.
    let _ = write!(
        s,
        "# {name}: FMI {fmi_version} co-simulation FMU from {TOOL} {version}

## The model

{about}

The spec is `{spec_path}` of the {TOOL} source (also in the FMU, as
`resources/model.json`). Every parameter is a tunable variable named by its
path, with the spec's value as its start value.

## The files

| file | what |
|---|---|
| `{name}.fmu` | the FMU, written by `{TOOL} export-fmu --model {spec_path} --fmi {flag} --name {name}` ({platform}) |
| `{name}_in.csv` | the input `x` at every communication point, t = {start} … {stop} s every {step} s: {input_about} |
| `{name}_ref.csv` | the reference output `y` at the same times |
| `{name}_ref.opt` | the settings: StartTime {start}, StopTime {stop}, StepSize {step}, RelTol {rel_tol} |

## How the reference was made

By `{TOOL} fmu-compat` ({TOOL} {version}) with the {TOOL} library, not
through the FMU: the spec built with the step size as its sample period
and run over the input. An importer sets the input at each communication
point `t_k` and calls `{do_step}(t_k, h)` (`h` the StepSize), which takes it
as the sample at `t_k + h`; so the reference's row at time 0 is the output
after initialization (input 0, initial state), and its row at `t_k + h` is
the output after the sample `x(t_k)`. The input's last row (at StopTime) is
not used.

## Reproducing it

With FMPy:

```
fmpy simulate {name}.fmu --input-file {name}_in.csv --start-time {start} --stop-time {stop} --output-interval {step} --output-file {name}_out.csv
```

With fmusim (Reference FMUs):

```
fmusim --interface-type cs --input-file {name}_in.csv --start-time {start} --stop-time {stop} --output-interval {step} --output-file {name}_out.csv {name}.fmu
```

The output `y` is expected to equal the reference within RelTol ({rel_tol},
relative to the largest |y|); the FMU has no solver, so the tolerance an
importer passes changes nothing. {TOOL}'s tests simulate this FMU with FMPy
this way and compare.
",
        fmi_version = fmi.number(),
        about = case.about,
        spec_path = case.spec_path,
        flag = fmi.flag(),
        platform = fmi.platform(),
        input_about = case.input_about,
        rel_tol = csvio::fmt_f64(REL_TOL),
        do_step = fmi.do_step(),
    );
    s
}

/// Creates `path` and its parents.
fn create_folder(path: &Path) -> Result<(), FmuCompatError> {
    std::fs::create_dir_all(path).map_err(|source| FmuCompatError::Folder {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes one model's folder for one FMI version, with the spec at
/// `spec_file`.
fn write_case(
    case: &Case,
    fmi: FmiVersion,
    folder: &Path,
    spec_file: &Path,
    binary: &FmuBinary,
) -> Result<(), FmuCompatError> {
    create_folder(folder)?;
    let times = case.times();
    let inputs: Vec<f64> = times.iter().map(|&t| (case.input)(t)).collect();
    let outputs = reference(case, &inputs)?;
    export_fmu::run(&ExportFmuOptions {
        model: spec_file.to_path_buf(),
        output: folder.join(format!("{}.fmu", case.name)),
        name: Some(case.name.to_string()),
        binary: binary.clone(),
        fmi: fmi.flag().to_string(),
    })?;
    let file = |suffix: &str| folder.join(format!("{}{suffix}", case.name));
    csvio::write_string_atomic(&file("_in.csv"), &csv_text("x", &times, &inputs))?;
    csvio::write_string_atomic(&file("_ref.csv"), &csv_text("y", &times, &outputs))?;
    csvio::write_string_atomic(&file("_ref.opt"), &ref_opt(case))?;
    csvio::write_string_atomic(&folder.join("ReadMe.md"), &readme(case, fmi))?;
    Ok(())
}

/// Writes the compatibility information; see the module docs.
pub fn run(opts: &FmuCompatOptions) -> Result<FmuCompatReport, FmuCompatError> {
    let versions = match opts.fmi.as_deref().and_then(FmiVersion::from_flag) {
        Some(only) => vec![only],
        None => vec![FmiVersion::V2, FmiVersion::V3],
    };
    let root = opts.dir.join("fmus");
    create_folder(&root)?;
    let specs = tempfile::tempdir().map_err(|source| FmuCompatError::Folder {
        path: std::env::temp_dir(),
        source,
    })?;
    let mut folders = Vec::new();
    for case in &CASES {
        let spec_file = specs.path().join(format!("{}.json", case.name));
        csvio::write_string_atomic(&spec_file, case.spec)?;
        for &fmi in &versions {
            let folder: PathBuf = [
                fmi.number(),
                "cs",
                fmi.platform(),
                TOOL,
                env!("CARGO_PKG_VERSION"),
                case.name,
            ]
            .iter()
            .collect();
            write_case(case, fmi, &root.join(&folder), &spec_file, &opts.binary)?;
            folders.push(folder);
        }
    }
    Ok(FmuCompatReport { root, folders })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_start_at_zero_and_reverse() {
        for case in &CASES {
            let times = case.times();
            assert_eq!(times.len(), case.steps + 1);
            assert_eq!(times[case.steps], case.stop());
            let x: Vec<f64> = times.iter().map(|&t| (case.input)(t)).collect();
            assert_eq!(x[0], 0.0, "{}", case.name);
            let reversals = x
                .windows(3)
                .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0)
                .count();
            assert!(reversals >= 10, "{}: {reversals}", case.name);
        }
    }

    #[test]
    fn the_reference_starts_with_the_initial_output_and_lags_the_input_by_a_step() {
        let case = &CASES[0];
        let x = [0.0, 0.5, 1.0, 0.2];
        let y = reference(case, &x).unwrap();
        let mut op = Spec::from_json(case.spec).unwrap().build().unwrap();
        let want: Vec<f64> = op.run(&x[..3]).unwrap();
        assert_eq!(y.len(), 4);
        assert_eq!(y[0], 0.0);
        assert_eq!(&y[1..], &want[..]);
    }

    #[test]
    fn files_follow_the_cross_check_conventions() {
        assert_eq!(
            csv_text("x", &[0.0, 0.5], &[1.0, -2.5e-7]),
            "\"time\",\"x\"\n0,1\n0.5,-2.5e-7\n"
        );
        assert_eq!(
            ref_opt(&CASES[0]),
            "StartTime, 0\nStopTime, 1\nStepSize, 0.001\nRelTol, 1e-12\n"
        );
        let opt = ref_opt(&CASES[1]);
        assert!(opt.contains("StepSize, 0.0013333333333333333\n"), "{opt}");
        let text = readme(&CASES[1], FmiVersion::V3);
        for needle in [
            "FMI 3.0 co-simulation FMU from hysteron",
            env!("CARGO_PKG_VERSION"),
            "fmi3DoStep",
            "x86_64-linux",
            "--stop-time 1.3333333333333333",
        ] {
            assert!(text.contains(needle), "{needle}: {text}");
        }
    }
}
