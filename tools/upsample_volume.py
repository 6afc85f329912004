#!/usr/bin/env python3
"""Upsample a 3D image by an integer factor (trilinear), as float32 NIfTI.

Makes the large test images of the scale measurements: the MNI template upsampled
by 2 (394×466×378 samples, 277 MB as float32) is about the size of a routine
clinical CT.

    python3 tools/upsample_volume.py IN.nii.gz OUT.nii [--factor 2]

The samples of OUT lie on the grid of IN refined `factor` times along each axis,
spanning the same first and last sample positions ((n - 1) * factor + 1 samples per
axis), so the affine keeps the first sample's position and divides the spacing by
`factor`. Needs nibabel, numpy and scipy (tools/requirements.txt).
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
    args = parser.parse_args()
    if args.factor < 1:
        parser.error("--factor must be at least 1")

    image = nibabel.load(args.input)
    samples = np.asarray(image.dataobj, dtype=np.float32)
    if samples.ndim != 3:
        parser.error(f"{args.input} has {samples.ndim} dimensions, not 3")
    shape = [(n - 1) * args.factor + 1 for n in samples.shape]
    coordinates = np.meshgrid(
        *[np.arange(n, dtype=np.float32) / args.factor for n in shape], indexing="ij"
    )
    upsampled = ndimage.map_coordinates(samples, coordinates, order=1).astype(np.float32)

    affine = image.affine.copy()
    affine[:3, :3] /= args.factor
    header = image.header.copy()
    header.set_data_dtype(np.float32)
    output = nibabel.Nifti1Image(upsampled, affine, header)
    output.set_qform(affine, code=int(image.header["qform_code"]) or 1)
    output.set_sform(affine, code=int(image.header["sform_code"]) or 1)
    nibabel.save(output, args.output)
    print(f"{args.output}: {upsampled.shape}, {upsampled.nbytes / 1e6:.0f} MB of samples")


if __name__ == "__main__":
    main()
