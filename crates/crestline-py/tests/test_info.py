"""``crestline info`` of an image prints the percentiles numpy computes (linear
interpolation between order statistics) on the samples nibabel reads, and the
world frame the file declares. Skipped without the tool (``cargo build
--release``) or nibabel."""

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"
MNI = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"


def test_info_prints_numpys_percentiles_and_the_frame():
    nibabel = pytest.importorskip("nibabel")
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    printed = subprocess.run([TOOL, "info", MNI], check=True, capture_output=True, text=True).stdout
    line = next(line for line in printed.splitlines() if line.startswith("percentiles"))
    pairs = re.findall(r"([\d.]+)%: (-?[\d.]+)", line)
    assert len(pairs) >= 5, line
    samples = np.asarray(nibabel.load(MNI).get_fdata(), dtype=np.float32).ravel()
    assert np.mean(samples == 0) > 0.75, "most of the template is background"
    for p, value in pairs:
        expected = np.percentile(samples.astype(np.float64), float(p))
        assert abs(float(value) - expected) <= 5e-5 * max(1.0, abs(expected)), (p, value, expected)
    assert re.search(r"world frame\s+RAS", printed), printed
