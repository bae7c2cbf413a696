//! CSV text → the series reader (time and value columns, as a case's `series` drive reads
//! them) and the measurement reader (identification). Both must refuse or accept any text
//! without panicking; what they accept must be finite and usable.
#![no_main]

use beamflow::io::measurement::{self, LoadOptions, Quantity};
use beamflow::signal::csv::{check_time_axis, parse_columns};
use beamflow::signal::voltage::VoltageInput;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(mut cols) = parse_columns(text, "fuzz.csv", &["t", "v"]) {
        let v = cols.pop().unwrap();
        let t = cols.pop().unwrap();
        assert_eq!(t.len(), v.len());
        assert!(t.iter().chain(&v).all(|x| x.is_finite()), "the reader passed a non-finite value");
        if check_time_axis("fuzz.csv", "t", &t, false).is_ok() {
            if let Ok(s) = VoltageInput::from_samples("fuzz.csv", t.clone(), v) {
                let (t0, t1) = (t[0], t[t.len() - 1]);
                for k in 0..=8 {
                    let x = s.value(t0 + (t1 - t0) * k as f64 / 8.0);
                    assert!(x.is_finite(), "interpolation gave {x}");
                }
                let _ = s.turning_points(t0, t1);
            }
        }
    }
    let _ = measurement::parse(text, "fuzz.csv", &[Quantity::Voltage], &LoadOptions::default());
});
