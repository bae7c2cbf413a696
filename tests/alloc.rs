//! The transient step allocates nothing, and the integrator's memory is linear in the
//! number of DOFs. A counting global allocator sees every allocation of this
//! test binary, so the tests here run one at a time under a lock.

use beamflow::analysis::plan::calibrated_model;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::solve::band_newmark::{BandNewmark, StepOptions};
use beamflow::solve::newmark::Scheme;
use std::alloc::{GlobalAlloc, Layout, System as Heap};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static SERIAL: Mutex<()> = Mutex::new(());

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { Heap.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { Heap.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn system(text: &str) -> System {
    let lc = LoadedCase::from_str(text, "alloc.toml", std::env::temp_dir()).unwrap();
    System::assemble(&calibrated_model(&lc).unwrap()).unwrap()
}

const FRAME: &str =
    "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";

#[test]
fn steps_allocate_nothing() {
    let _serial = SERIAL.lock().unwrap();
    let model = calibrated_model(&LoadedCase::from_str(FRAME, "alloc.toml", std::env::temp_dir()).unwrap()).unwrap();
    let sys = System::assemble(&model).unwrap();
    let rayleigh = (model.rayleigh().a0, model.rayleigh().a1);
    for scheme in [Scheme::average_acceleration(), Scheme::generalized_alpha(0.8)] {
        let options = StepOptions { rayleigh: Some(rayleigh), track_dissipation: true, ..StepOptions::default() };
        let mut nm = BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, 1e-4, options).unwrap();
        // The proportional form's R term (the frame's entries) must not allocate either.
        assert!(nm.uses_proportional_damping());
        nm.set_load_patterns(sys.drives.clone());
        let pairs: Vec<(usize, f64)> = sys.drives[0].clone();
        // Warm up: the first steps size the load bookkeeping (with α_f a step also reloads
        // the previous step's pairs, so it takes two to reach full size).
        nm.step(&pairs);
        nm.step(&pairs);
        nm.step_weighted(&[1.0]);
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for k in 0..1000 {
            let s = (k as f64 * 0.1).sin();
            if k % 2 == 0 {
                nm.step_weighted(&[s]);
            } else {
                nm.step(&pairs);
            }
        }
        let after = ALLOCATIONS.load(Ordering::SeqCst);
        assert_eq!(after - before, 0, "{scheme:?}: the step loop allocated {} times", after - before);
    }
}

#[test]
fn integrator_memory_is_linear_in_dofs() {
    let _serial = SERIAL.lock().unwrap();
    let per_dof = |elements: usize| {
        let sys = system(&format!(
            "[beam.mesh]\nelements = {elements}\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n"
        ));
        let scheme = Scheme::average_acceleration();
        let nm = BandNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, scheme, 1e-4, StepOptions::default()).unwrap();
        nm.memory_bytes() as f64 / sys.n() as f64
    };
    let (small, large) = (per_dof(500), per_dof(50_000));
    // A dense n×n anywhere would multiply the per-DOF memory by 100 between these sizes.
    assert!((large / small - 1.0).abs() < 0.05, "{small} vs {large} bytes per DOF");
    assert!(large < 400.0, "{large} bytes per DOF");
}
