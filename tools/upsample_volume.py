#!/usr/bin/env python3
"""Upsample a 3D image (trilinear), as float32 NIfTI.

Makes the large test images of the scale measurements: the MNI template upsampled
by 2 (393×465×377 samples, 276 MB as float32) is about the size of a routine
clinical CT; resampled to 512×512×1000 samples (1 GB), that of a whole-body CT.

    python3 tools/upsample_volume.py IN.nii.gz OUT.nii [--factor 2 | --shape NX NY NZ]

The samples of OUT span the same first and last sample positions as IN's: with
`--factor F`, (n - 1) F + 1 samples per axis; with `--shape`, the given numbers. The
affine keeps the first sample's position and scales the spacing to match. Needs
nibabel, numpy and scipy (tools/requirements.txt).
"""

import argparse

import nibabel
import numpy as np
from scipy import ndimage


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("--factor", type=int, default=2)
    parser.add_argument("--shape", type=int, nargs=3, metavar=("NX", "NY", "NZ"))
    args = parser.parse_args()
    if args.factor < 1:
        parser.error("--factor must be at least 1")
    if args.shape and min(args.shape) < 2:
        parser.error("--shape needs at least 2 samples per axis")

    image = nibabel.load(args.input)
    samples = np.asarray(image.dataobj, dtype=np.float32)
    if samples.ndim != 3:
        parser.error(f"{args.input} has {samples.ndim} dimensions, not 3")
    shape = args.shape or [(n - 1) * args.factor + 1 for n in samples.shape]
    steps = [(n - 1) / (m - 1) for n, m in zip(samples.shape, shape)]
    upsampled = np.empty(shape, dtype=np.float32)
    # One output slice at a time, to keep the coordinate arrays small.
    xy = np.meshgrid(
        *[np.arange(m, dtype=np.float64) * step for m, step in zip(shape[:2], steps[:2])],
        indexing="ij",
    )
    for k in range(shape[2]):
        z = np.full(xy[0].shape, k * steps[2])
        upsampled[:, :, k] = ndimage.map_coordinates(samples, [*xy, z], order=1)

    affine = image.affine.copy()
    affine[:3, :3] *= np.array(steps)[np.newaxis, :]
    header = image.header.copy()
    header.set_data_dtype(np.float32)
    output = nibabel.Nifti1Image(upsampled, affine, header)
    output.set_qform(affine, code=int(image.header["qform_code"]) or 1)
    output.set_sform(affine, code=int(image.header["sform_code"]) or 1)
    nibabel.save(output, args.output)
    print(f"{args.output}: {upsampled.shape}, {upsampled.nbytes / 1e6:.0f} MB of samples")


if __name__ == "__main__":
    main()
