//! `crestline info <volume>` prints the exact percentiles of the image's values
//! (numpy's `np.percentile`, linear interpolation), here checked on the MNI T1
//! template, where most voxels are background zeros.

use std::path::Path;
use std::process::Command;

const MNI: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../volumes/mni152_t1_1mm.nii.gz"
);

/// The percentiles the tool lists.
const PERCENTILES: [f64; 7] = [1.0, 5.0, 25.0, 50.0, 75.0, 95.0, 99.0];

/// The `p`-th percentile of the `sorted` finite samples: the value at rank
/// (n − 1)·p/100, interpolated linearly between the two samples around it.
fn sorted_percentile(sorted: &[f64], p: f64) -> f64 {
    let rank = (sorted.len() - 1) as f64 * (p / 100.0);
    let below = rank.floor() as usize;
    let above = (below + 1).min(sorted.len() - 1);
    let t = rank - below as f64;
    sorted[below] + t * (sorted[above] - sorted[below])
}

#[test]
fn info_prints_the_exact_percentiles_of_the_mni_template() {
    if !Path::new(MNI).exists() {
        crate::common::skip(&format!("{MNI} is absent"));
        return;
    }
    let volume = crestline::io::read_volume(Path::new(MNI)).unwrap();
    let mut sorted: Vec<f64> = volume
        .samples()
        .iter()
        .filter(|v| v.is_finite())
        .map(|&v| f64::from(v))
        .collect();
    sorted.sort_by(f64::total_cmp);
    let zeros = sorted.iter().filter(|&&v| v == 0.0).count();
    assert!(
        zeros as f64 > 0.75 * sorted.len() as f64,
        "{zeros} zeros of {}",
        sorted.len()
    );
    let exact: Vec<f64> = PERCENTILES
        .iter()
        .map(|&p| sorted_percentile(&sorted, p))
        .collect();
    // More than 75% of the voxels are background: up to the 75th percentile all
    // are 0 (a 64-bin histogram would put them at 0.05, 0.25, 1.27, 2.55 and 3.82).
    assert_eq!(exact[..5], [0.0; 5]);

    let out = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(["info", MNI])
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("percentiles"))
        .unwrap_or_else(|| panic!("no percentiles line in\n{text}"))
        .trim();
    let expected = PERCENTILES
        .iter()
        .zip(&exact)
        .map(|(p, v)| format!("{p}%: {v:.4}"))
        .collect::<Vec<_>>()
        .join("  ");
    assert_eq!(line, expected, "in\n{text}");
}
