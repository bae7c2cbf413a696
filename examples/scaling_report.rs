//! Reads the `scaling` benchmark's results (run `cargo bench --bench scaling` first), fits
//! time per step ∝ DOFs^p by least squares in log–log, prints the table and the exponent,
//! and draws `docs/img/scaling.png` (time per step and time per DOF-step against DOFs).
//!
//! `cargo run --release --example scaling_report [-- <criterion dir> <output png>]`

use beamflow::report::plot::{LinePlot, Series};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = args.get(1).map(PathBuf::from).unwrap_or(root.join("target/criterion/scaling/newmark_step"));
    let out = args.get(2).map(PathBuf::from).unwrap_or(root.join("docs/img/scaling.png"));
    let mut points: Vec<(f64, f64)> = Vec::new();
    for entry in std::fs::read_dir(&dir).map_err(|e| format!("{}: {e} (run the scaling bench first)", dir.display()))? {
        let entry = entry?;
        let Ok(n) = entry.file_name().to_string_lossy().parse::<f64>() else { continue };
        let est = entry.path().join("new/estimates.json");
        let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&est)?)?;
        let ns = json["median"]["point_estimate"].as_f64().ok_or(format!("{}: no median", est.display()))?;
        points.push((n, ns * 1e-9));
    }
    if points.len() < 2 {
        return Err(format!("{}: fewer than two sizes measured", dir.display()).into());
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|&(n, t)| (n.ln(), t.ln())).unzip();
    let k = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / k, ly.iter().sum::<f64>() / k);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    let p = sxy / sxx;
    println!("| DOFs | time per step | ns per DOF-step |\n|---|---|---|");
    for &(n, t) in &points {
        println!("| {n:.0} | {:.3} µs | {:.1} |", t * 1e6, t * 1e9 / n);
    }
    println!("\nleast-squares exponent p (time ∝ DOFs^p): {p:.3}");
    let mut plot = LinePlot::new(
        format!("Newmark step cost against size (fit exponent {p:.3})"),
        "degrees of freedom",
        "time (s)",
    );
    plot.log_x = true;
    plot.log_y = true;
    let (n, t): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
    plot.series.push(Series::line("time per step (s)", n.clone(), t.clone()));
    plot.series.push(Series::line("time per DOF-step (s)", n.clone(), n.iter().zip(&t).map(|(n, t)| t / n).collect()));
    let c = (my - p * mx).exp();
    plot.series.push(Series::line(format!("fit c·n^{p:.3}"), n.clone(), n.iter().map(|n| c * n.powf(p)).collect()));
    plot.render(&out)?;
    println!("wrote {}", out.display());
    Ok(())
}
