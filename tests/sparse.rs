//! The sparse LDLᵀ and the shift-invert Lanczos on it: solves against faer's dense Cholesky,
//! plate modes against the profile path, the inertia against the eigenvalues below the
//! shift (Sturm), a singular M against a dense reference with its massless DOFs condensed
//! out, and errors for a singular K.

mod common;

use beamflow::analysis::modes;
use beamflow::case::build::build_structure;
use beamflow::linalg::{Csr, SparsePattern};
use beamflow::solve::eigen;
use beamflow::solve::lanczos::{modes_shift_invert, modes_sparse};
use common::*;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// The example plate of spec §16 (0.5 × 0.4 × 0.003 m aluminium) with `edges` on every side.
fn plate(edges: &str, nx: usize, ny: usize) -> beamflow::assembly::System {
    let text = format!(
        "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\npoisson_ratio = 0.33\n\
         density = 2700.0\n[plate.mesh]\nelements = [{nx}, {ny}]\n\
         [plate.edges]\nx0 = \"{edges}\"\nx1 = \"{edges}\"\ny0 = \"{edges}\"\ny1 = \"{edges}\"\n"
    );
    modes::bare_system(&build_structure(&case(&text)).unwrap()).unwrap()
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64) / ((1u64 << 53) as f64) - 0.5
}

/// A random symmetric matrix with `per_row` off-diagonal entries a row, made positive
/// definite by diagonal dominance.
fn random_spd(n: usize, per_row: usize, seed: &mut u64) -> Csr {
    let mut trip = Vec::new();
    let mut diag = vec![1.0; n];
    for i in 0..n {
        for _ in 0..per_row {
            let j = ((lcg(seed) + 0.5) * n as f64) as usize % n;
            let v = lcg(seed);
            if i != j {
                trip.push((i, j, v));
                trip.push((j, i, v));
                diag[i] += v.abs();
                diag[j] += v.abs();
            }
        }
    }
    trip.extend(diag.iter().enumerate().map(|(i, &d)| (i, i, d)));
    Csr::from_triplets(n, &trip)
}

fn dense(a: &Csr) -> Mat<f64> {
    let n = a.dim();
    let d = a.to_dense();
    Mat::from_fn(n, n, |i, j| d[i * n + j])
}

/// Solves of two combinations on one analysed pattern match faer's dense Cholesky.
#[test]
fn random_spd_solves_match_dense_cholesky() {
    let mut seed = 11;
    let n = 600;
    let a = random_spd(n, 4, &mut seed);
    let b = Csr::from_triplets(n, &(0..n).map(|i| (i, i, 0.5 + lcg(&mut seed))).collect::<Vec<_>>());
    let pattern = SparsePattern::analyse(&[&a, &b]).unwrap();
    assert!(pattern.factor_bytes() > 0);
    let rhs: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
    for shift in [0.0, 0.3] {
        let fac = pattern.factorize(&[(1.0, &a), (-shift, &b)]).unwrap();
        assert_eq!(fac.negative_pivots(), 0);
        let mut x = rhs.clone();
        fac.solve_in_place(&mut x);
        let want = (dense(&a) - shift * dense(&b)).llt(Side::Lower).unwrap().solve(Mat::from_fn(n, 1, |i, _| rhs[i]));
        let scale = (0..n).map(|i| want[(i, 0)].abs()).fold(0.0, f64::max);
        for i in 0..n {
            assert!(
                (x[i] - want[(i, 0)]).abs() < 1e-12 * scale,
                "shift {shift}, row {i}: {} vs {}",
                x[i],
                want[(i, 0)]
            );
        }
    }
}

/// Modes of a simply supported plate through the sparse LDLᵀ equal those through the
/// profile LDLᵀ, frequencies to 1e-10 and the first shape to 1e-8.
#[test]
fn plate_modes_match_the_profile_path() {
    let sys = plate("simply_supported", 24, 20);
    let profile = modes_shift_invert(&sys.k, &sys.m, &sys.envelope, 12, 0.0).unwrap();
    let sparse = modes_sparse(&sys.k, &sys.m, 12, 0.0).unwrap();
    assert_eq!(sparse.count(), 12);
    for (r, (a, b)) in profile.omega.iter().zip(&sparse.omega).enumerate() {
        assert!(rel(*b, *a).abs() < 1e-10, "mode {r}: {b} vs {a}");
    }
    let n = sys.n();
    let (a, b) = (profile.shape_global(0, n), sparse.shape_global(0, n));
    let big = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-8 * big));
}

/// The number of negative pivots of K − σM equals the number of eigenvalues below σ,
/// between every pair of the first ten modes of a clamped plate.
#[test]
fn inertia_counts_the_plate_eigenvalues_below_the_shift() {
    let sys = plate("clamped", 14, 12);
    let all = eigen::modes(&sys.k, &sys.m, &(0..sys.n()).collect::<Vec<_>>(), 11).unwrap();
    let pattern = SparsePattern::analyse(&[&sys.k, &sys.m]).unwrap();
    for below in 0..=10 {
        let lam = |r: usize| all.omega[r] * all.omega[r];
        let sigma = if below == 0 { 0.5 * lam(0) } else { 0.5 * (lam(below - 1) + lam(below)) };
        let fac = pattern.factorize(&[(1.0, &sys.k), (-sigma, &sys.m)]).unwrap();
        assert_eq!(fac.negative_pivots(), below, "σ = {sigma:e}");
    }
}

/// A chain of springs (K positive definite) with a third of its DOFs massless: the modes
/// equal those of the dense problem with the massless DOFs condensed out, and each shape
/// satisfies K·x = λ·M·x on every DOF, massless ones included.
#[test]
fn singular_mass_matches_the_condensed_dense_problem() {
    let n = 60;
    let mut seed = 5;
    let mut kt = Vec::new();
    for i in 0..n {
        kt.push((i, i, 2.5));
        if i + 1 < n {
            kt.extend([(i, i + 1, -1.0), (i + 1, i, -1.0)]);
        }
        if i + 2 < n {
            kt.extend([(i, i + 2, -0.2), (i + 2, i, -0.2)]);
        }
    }
    let k = Csr::from_triplets(n, &kt);
    let mass: Vec<f64> = (0..n).map(|i| if i % 3 == 2 { 0.0 } else { 1.0 + 0.4 * lcg(&mut seed) }).collect();
    let m = Csr::from_triplets(n, &mass.iter().enumerate().map(|(i, &v)| (i, i, v)).collect::<Vec<_>>());
    let count = 6;
    let got = modes_sparse(&k, &m, count, 0.0).unwrap();
    assert_eq!(got.count(), count);

    // Reference: K_red = K_mm − K_m0·K_00⁻¹·K_0m on the massive DOFs, then the symmetric
    // eigenproblem of M_mm^-½·K_red·M_mm^-½.
    let kd = dense(&k);
    let (massive, massless): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| mass[i] > 0.0);
    let sub = |r: &[usize], c: &[usize]| Mat::from_fn(r.len(), c.len(), |i, j| kd[(r[i], c[j])]);
    let k00 = sub(&massless, &massless);
    let k0m = sub(&massless, &massive);
    let kred = sub(&massive, &massive) - k0m.transpose() * k00.llt(Side::Lower).unwrap().solve(&k0m);
    let s = |i: usize| mass[massive[i]].sqrt();
    let reduced = Mat::from_fn(massive.len(), massive.len(), |i, j| kred[(i, j)] / (s(i) * s(j)));
    let evd = reduced.self_adjoint_eigen(Side::Lower).unwrap();
    let lam_ref = evd.S().column_vector();
    for r in 0..count {
        let (lam, want) = (got.omega[r] * got.omega[r], lam_ref[r]);
        assert!(rel(lam, want).abs() < 1e-10, "mode {r}: λ = {lam} vs {want}");
        let x = got.shape_global(r, n);
        let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
        k.mul_vec(&x, &mut kx);
        m.mul_vec(&x, &mut mx);
        let scale = kx.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..n {
            assert!((kx[i] - lam * mx[i]).abs() < 1e-9 * scale, "mode {r}, DOF {i} (mass {})", mass[i]);
        }
        let mnorm: f64 = x.iter().zip(&mx).map(|(a, b)| a * b).sum();
        assert!((mnorm - 1.0).abs() < 1e-10, "mode {r}: xᵀMx = {mnorm}");
    }
}

/// A plate with free edges has rigid motions: at σ = 0 its K is singular, and the sparse
/// path factorises it shifted by a little of M instead: the three rigid-body modes first,
/// then the dense solver's elastic modes. Its inertia counts the rigid motions.
#[test]
fn free_plate_at_zero_shift_is_shifted() {
    let sys = plate("free", 12, 10);
    let sparse = sparse_and_dense_agree(&sys.k, &sys.m, 3..6, 1e-10);
    assert!(sparse.omega[..3].iter().all(|w| w * w < 1e-9 * sparse.omega[3].powi(2)), "{:?}", sparse.omega);
    // Shifted below the rigid modes (λ = 0) the same model factorises, with the inertia of
    // a negative shift: no eigenvalue below.
    let pattern = SparsePattern::analyse(&[&sys.k, &sys.m]).unwrap();
    let lowest_flexible = {
        let all = eigen::modes(&sys.k, &sys.m, &(0..sys.n()).collect::<Vec<_>>(), 4).unwrap();
        all.omega[3] * all.omega[3]
    };
    let fac = pattern.factorize(&[(1.0, &sys.k), (0.1 * lowest_flexible, &sys.m)]).unwrap();
    assert_eq!(fac.negative_pivots(), 0);
    let fac = pattern.factorize(&[(1.0, &sys.k), (-0.5 * lowest_flexible, &sys.m)]).unwrap();
    assert_eq!(fac.negative_pivots(), 3, "three rigid motions below a positive shift");
}

/// A plate above the dense solver's size takes the sparse path in the modal analysis: the
/// frequencies agree with the profile path's.
#[test]
fn modal_analysis_of_a_large_plate_takes_the_sparse_path() {
    let text = "[plate]\nlength_x = 0.5\nlength_y = 0.4\nthickness = 0.003\nyoungs_modulus = 70e9\n\
                poisson_ratio = 0.33\ndensity = 2700.0\n[plate.mesh]\nelements = [30, 24]\n[plate.edges]\n\
                x0 = \"clamped\"\nx1 = \"simply_supported\"\ny0 = \"clamped\"\ny1 = \"simply_supported\"\n";
    let structure = build_structure(&case(text)).unwrap();
    let sys = modes::bare_system(&structure).unwrap();
    assert!(sys.n() > modes::DENSE_EIGEN_LIMIT);
    let got = modes::run(&structure, 8).unwrap().modes;
    let profile = modes_shift_invert(&sys.k, &sys.m, &sys.envelope, 8, 0.0).unwrap();
    for (a, b) in got.omega.iter().zip(&profile.omega) {
        assert!(rel(*a, *b).abs() < 1e-10, "{a} vs {b}");
    }
}

/// A cancelled request stops the Lanczos run at its next vector with `Cancelled`.
#[test]
fn cancellation_stops_the_sparse_lanczos_run() {
    use beamflow::progress::{cancellable, Cancel};
    let sys = plate("simply_supported", 12, 10);
    let cancel = Cancel::new();
    cancel.cancel();
    let got = cancellable(cancel, || modes_sparse(&sys.k, &sys.m, 4, 0.0));
    assert!(matches!(got, Err(beamflow::error::Error::Cancelled)), "{got:?}");
}

/// A factorisation long enough to notice shows on the progress bars: begun, then done,
/// before the Lanczos vectors; a small one does not.
#[test]
fn a_large_factorisation_reports_its_progress() {
    use beamflow::progress::{observe, Log};
    for (nx, ny, shown) in [(60, 50, true), (12, 10, false)] {
        let sys = plate("simply_supported", nx, ny);
        let log = Log::default();
        observe(std::rc::Rc::new(log.clone()), || modes_sparse(&sys.k, &sys.m, 4, 0.0)).unwrap();
        let lines = log.0.borrow();
        let factor = lines.iter().position(|l| l.starts_with("start LDLᵀ of"));
        assert_eq!(factor.is_some(), shown, "{nx} × {ny}: {lines:?}");
        if let Some(i) = factor {
            assert!(lines[i + 1].starts_with("LDLᵀ of") && lines[i + 1].ends_with(" 1 "), "{lines:?}");
            let lanczos = lines.iter().position(|l| l.contains("Lanczos vectors")).expect("the Lanczos bar");
            assert!(lanczos > i + 1, "{lines:?}");
        }
    }
}

/// A held plate with a link 10⁹ times stiffer than its stiffest DOF between two
/// neighbouring nodes' w: its factor has a pivot ≈ 10⁻⁹ of the diagonal, which is stiffness,
/// not a rigid motion. Neither solver shifts it (shifted, the dense solver put mode 1 4 %
/// high and the sparse one missed modes): the two agree, and each mode's frequency is its
/// Rayleigh quotient, the link's energy k·(φ_a − φ_b)² taken apart from the plate's so
/// that no large term cancels.
#[test]
fn a_stiff_link_in_a_held_plate_is_not_taken_for_a_rigid_motion() {
    let sys = plate("simply_supported", 20, 16);
    let n = sys.n();
    let big = (0..n).map(|i| sys.k.get(i, i)).fold(0.0f64, f64::max);
    let w: Vec<usize> = (0..n).filter(|&i| sys.k.get(i, i) > 0.0 && sys.m.get(i, i) > 0.0).take(200).collect();
    let (a, b) = (w[150], (w[151..].iter().copied().find(|&j| sys.k.get(w[150], j) != 0.0)).unwrap_or(w[151]));
    let kl = 1e9 * big;
    let link = Csr::from_triplets(n, &[(a, a, kl), (b, b, kl), (a, b, -kl), (b, a, -kl)]);
    let k = Csr::combine(&[(1.0, &sys.k), (1.0, &link)]);
    // K itself is 10⁹ times worse conditioned: round-off of ~1e-7 in either solver.
    let sparse = sparse_and_dense_agree(&k, &sys.m, 0..6, 1e-5);
    for r in 0..6 {
        let phi = sparse.shape_global(r, n);
        let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
        sys.k.mul_vec(&phi, &mut kx);
        sys.m.mul_vec(&phi, &mut mx);
        let dot = |u: &[f64]| phi.iter().zip(u).map(|(p, q)| p * q).sum::<f64>();
        let rq = (dot(&kx) + kl * (phi[a] - phi[b]).powi(2)) / dot(&mx);
        assert!(
            rel(rq.sqrt(), sparse.omega[r]) < 1e-6,
            "mode {}: Rayleigh {} vs {}",
            r + 1,
            rq.sqrt(),
            sparse.omega[r]
        );
    }
}

/// The lowest six modes of (K, M) from the sparse solver (σ = 0) and the dense one, their
/// frequencies `modes` within `tol` of each other: the sparse modes.
fn sparse_and_dense_agree(k: &Csr, m: &Csr, modes: std::ops::Range<usize>, tol: f64) -> beamflow::solve::eigen::Modes {
    let sparse = modes_sparse(k, m, 6, 0.0).unwrap();
    let dense = eigen::modes(k, m, &(0..k.dim()).collect::<Vec<_>>(), 6).unwrap();
    for r in modes {
        let (a, b) = (sparse.omega[r], dense.omega[r]);
        assert!(rel(a, b) < tol, "mode {}: {a} vs {b}", r + 1);
    }
    sparse
}
