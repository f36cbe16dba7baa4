//! The cost of one step of the paper model through each face, in one run:
//! `Operator::trial` + `commit` in Rust, `hysteron_step` of the C API, and
//! a host's step through the FMU's binary (set the input, do the step, get
//! the output) in FMI 2.0 and FMI 3.0. Every face runs the same model on
//! the same input; the differences are what each face adds.
//!
//! `cargo bench -p hysteron-c --bench step_overhead`
//!
//! The FMI functions are those `libhysteron_c.so` exports to hosts, called
//! through their C symbols as a host calls them (without the dynamic
//! loader's indirection), each instance instantiated from a resource folder
//! holding the model's spec, as `hysteron export-fmu` packs it.
#![allow(non_snake_case)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hysteron::models::Spec;
use hysteron::Operator;
use hysteron_c::c_api::{
    hysteron_model_free, hysteron_model_from_json, hysteron_reset, hysteron_step,
};
use hysteron_c::fmu::{guid, VR_X, VR_Y};
use hysteron_c::{HysteronModel, HysteronStatus};
use std::ffi::{c_char, c_int, c_void, CString};
use std::hint::black_box;
use std::path::PathBuf;

/// `fmi2CallbackFunctions`, without a logger (allowed: the FMU then logs
/// nothing).
#[repr(C)]
struct Fmi2Callbacks {
    logger: *const c_void,
    allocate_memory: *const c_void,
    free_memory: *const c_void,
    step_finished: *const c_void,
    component_environment: *mut c_void,
}

extern "C" {
    fn fmi2Instantiate(
        name: *const c_char,
        kind: c_int,
        guid: *const c_char,
        resources: *const c_char,
        functions: *const Fmi2Callbacks,
        visible: c_int,
        logging_on: c_int,
    ) -> *mut c_void;
    fn fmi2SetupExperiment(
        c: *mut c_void,
        tolerance_defined: c_int,
        tolerance: f64,
        start: f64,
        stop_defined: c_int,
        stop: f64,
    ) -> c_int;
    fn fmi2EnterInitializationMode(c: *mut c_void) -> c_int;
    fn fmi2ExitInitializationMode(c: *mut c_void) -> c_int;
    fn fmi2SetReal(c: *mut c_void, vr: *const u32, n: usize, v: *const f64) -> c_int;
    fn fmi2DoStep(c: *mut c_void, t: f64, h: f64, no_prior: c_int) -> c_int;
    fn fmi2GetReal(c: *mut c_void, vr: *const u32, n: usize, v: *mut f64) -> c_int;
    fn fmi2Reset(c: *mut c_void) -> c_int;
    fn fmi2FreeInstance(c: *mut c_void);

    #[allow(clippy::too_many_arguments)]
    fn fmi3InstantiateCoSimulation(
        name: *const c_char,
        token: *const c_char,
        resources: *const c_char,
        visible: bool,
        logging_on: bool,
        event_mode_used: bool,
        early_return_allowed: bool,
        required: *const u32,
        n_required: usize,
        environment: *mut c_void,
        log: *const c_void,
        intermediate_update: *const c_void,
    ) -> *mut c_void;
    fn fmi3EnterInitializationMode(
        c: *mut c_void,
        tolerance_defined: bool,
        tolerance: f64,
        start: f64,
        stop_defined: bool,
        stop: f64,
    ) -> c_int;
    fn fmi3ExitInitializationMode(c: *mut c_void) -> c_int;
    fn fmi3SetFloat64(
        c: *mut c_void,
        vr: *const u32,
        n_vr: usize,
        v: *const f64,
        n: usize,
    ) -> c_int;
    #[allow(clippy::too_many_arguments)]
    fn fmi3DoStep(
        c: *mut c_void,
        t: f64,
        h: f64,
        no_prior: bool,
        event_handling_needed: *mut bool,
        terminate: *mut bool,
        early_return: *mut bool,
        last_successful_time: *mut f64,
    ) -> c_int;
    fn fmi3GetFloat64(c: *mut c_void, vr: *const u32, n_vr: usize, v: *mut f64, n: usize) -> c_int;
    fn fmi3Reset(c: *mut c_void) -> c_int;
    fn fmi3FreeInstance(c: *mut c_void);
}

/// Samples per measured block: slow reversals with a ripple, as in the
/// C API's benchmark (`examples/c/bench_fmi.c`).
const N: usize = 4_000;
/// The communication step.
const H: f64 = 1e-3;

fn input() -> Vec<f64> {
    (0..N)
        .map(|i| {
            let t = i as f64;
            2.5 * (std::f64::consts::TAU * t / 2000.0).sin()
                + 0.3 * (std::f64::consts::TAU * t / 97.3).sin()
        })
        .collect()
}

/// The paper model's spec, and a resource folder holding it as
/// `model.json` (as in an exported FMU).
fn paper() -> (String, PathBuf) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let json = std::fs::read_to_string(root.join("examples/specs/paper.json"))
        .expect("examples/specs/paper.json");
    let resources =
        std::env::temp_dir().join(format!("hysteron-step-bench-{}", std::process::id()));
    std::fs::create_dir_all(&resources).expect("a temporary folder");
    std::fs::write(resources.join("model.json"), &json).expect("a writable temporary folder");
    (json, resources)
}

/// One run of the input through the model as `Operator::trial` +
/// `commit`, from its initial state; the sum of the outputs.
fn run_operator(m: &mut dyn Operator<f64>, x: &[f64]) -> f64 {
    m.reset();
    let mut sum = 0.0;
    for &xi in x {
        sum += m.trial(xi).expect("a step").output;
        m.commit();
    }
    sum
}

/// The same through `hysteron_step`.
///
/// # Safety
/// `handle` is a live model of the C API.
unsafe fn run_c_api(handle: *mut HysteronModel, x: &[f64]) -> f64 {
    unsafe { hysteron_reset(handle) };
    let mut sum = 0.0;
    for &xi in x {
        let mut y = 0.0;
        let s = unsafe { hysteron_step(handle, xi, &mut y) };
        assert!(s == HysteronStatus::Ok, "hysteron_step");
        sum += y;
    }
    sum
}

/// The same as an FMI 2.0 host steps it: reset and initialise, then per
/// sample `fmi2SetReal`, `fmi2DoStep`, `fmi2GetReal`.
///
/// # Safety
/// `c` is a live FMI 2.0 instance.
unsafe fn run_fmi2(c: *mut c_void, x: &[f64]) -> f64 {
    unsafe {
        assert_eq!(fmi2Reset(c), 0);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), 0);
        assert_eq!(fmi2EnterInitializationMode(c), 0);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
        let (mut t, mut sum) = (0.0, 0.0);
        for &xi in x {
            let mut y = 0.0;
            let s = fmi2SetReal(c, &VR_X, 1, &xi)
                | fmi2DoStep(c, t, H, 1)
                | fmi2GetReal(c, &VR_Y, 1, &mut y);
            assert_eq!(s, 0, "an FMI 2.0 step");
            t += H;
            sum += y;
        }
        sum
    }
}

/// The same as an FMI 3.0 host steps it: reset and initialise, then per
/// sample `fmi3SetFloat64`, `fmi3DoStep`, `fmi3GetFloat64`.
///
/// # Safety
/// `c` is a live FMI 3.0 co-simulation instance.
unsafe fn run_fmi3(c: *mut c_void, x: &[f64]) -> f64 {
    unsafe {
        assert_eq!(fmi3Reset(c), 0);
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            0
        );
        assert_eq!(fmi3ExitInitializationMode(c), 0);
        let (mut t, mut sum) = (0.0, 0.0);
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        for &xi in x {
            let mut y = 0.0;
            let s = fmi3SetFloat64(c, &VR_X, 1, &xi, 1)
                | fmi3DoStep(
                    c,
                    t,
                    H,
                    true,
                    &mut event,
                    &mut terminate,
                    &mut early,
                    &mut last,
                )
                | fmi3GetFloat64(c, &VR_Y, 1, &mut y, 1);
            assert_eq!(s, 0, "an FMI 3.0 step");
            t += H;
            sum += y;
        }
        sum
    }
}

fn step_overhead(c: &mut Criterion) {
    let x = input();
    let (json, resources) = paper();
    let c_str = |s: &str| CString::new(s).expect("no NUL");
    let (token, name) = (c_str(&guid(&json)), c_str("bench"));
    let uri = c_str(&format!("file://{}", resources.display()));
    let dir = c_str(&resources.display().to_string());

    let mut model = Spec::from_json(&json)
        .and_then(|s| s.build())
        .expect("paper.json builds");
    let mut handle: *mut HysteronModel = std::ptr::null_mut();
    // SAFETY: a NUL-terminated string and a place for the handle.
    let status = unsafe { hysteron_model_from_json(c_str(&json).as_ptr(), &mut handle) };
    assert!(status == HysteronStatus::Ok, "hysteron_model_from_json");
    let callbacks = Fmi2Callbacks {
        logger: std::ptr::null(),
        allocate_memory: std::ptr::null(),
        free_memory: std::ptr::null(),
        step_finished: std::ptr::null(),
        component_environment: std::ptr::null_mut(),
    };
    // SAFETY: NUL-terminated strings, callbacks that outlive the instance.
    let c2 = unsafe {
        fmi2Instantiate(
            name.as_ptr(),
            1,
            token.as_ptr(),
            uri.as_ptr(),
            &callbacks,
            0,
            0,
        )
    };
    assert!(!c2.is_null(), "fmi2Instantiate");
    // SAFETY: NUL-terminated strings; no callbacks.
    let c3 = unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            dir.as_ptr(),
            false,
            false,
            false,
            false,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    assert!(!c3.is_null(), "fmi3InstantiateCoSimulation");

    // Every face computes the same outputs, bit for bit.
    let sum = run_operator(&mut *model, &x);
    // SAFETY: live handles and instances.
    let faces = unsafe { [run_c_api(handle, &x), run_fmi2(c2, &x), run_fmi3(c3, &x)] };
    for f in faces {
        assert_eq!(f.to_bits(), sum.to_bits(), "a face's outputs differ");
    }

    let mut g = c.benchmark_group("paper model step");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("Operator::trial + commit", |b| {
        b.iter(|| black_box(run_operator(&mut *model, &x)))
    });
    // SAFETY (all three): live handles and instances, freed after.
    g.bench_function("hysteron_step", |b| {
        b.iter(|| black_box(unsafe { run_c_api(handle, &x) }))
    });
    g.bench_function("fmi2SetReal + fmi2DoStep + fmi2GetReal", |b| {
        b.iter(|| black_box(unsafe { run_fmi2(c2, &x) }))
    });
    g.bench_function("fmi3SetFloat64 + fmi3DoStep + fmi3GetFloat64", |b| {
        b.iter(|| black_box(unsafe { run_fmi3(c3, &x) }))
    });
    g.finish();
    // SAFETY: made above, each freed once.
    unsafe {
        hysteron_model_free(handle);
        fmi2FreeInstance(c2);
        fmi3FreeInstance(c3);
    }
    let _ = std::fs::remove_dir_all(&resources);
}

criterion_group!(benches, step_overhead);
criterion_main!(benches);
