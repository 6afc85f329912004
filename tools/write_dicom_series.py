#!/usr/bin/env python3
"""Write a CT-like DICOM series (one file per slice) from a NIfTI volume.

    python3 tools/write_dicom_series.py volumes/mni152_t1_1mm.nii.gz OUT_DIR
        [--syntax explicit|implicit|big|deflated|rle] [--rotate DEG]
        [--slices A:B] [--shuffle] [--seed N]
        [--drop-slice K] [--tilt DEG] [--second-series] [--mixed-orientation]

Slice k of the series is the NIfTI's plane k (rows along j, columns along i).
Positions and orientations are the NIfTI affine's, converted from RAS to LPS (the
DICOM patient frame: x and y change sign). Samples are stored as signed 16-bit
values with Rescale Slope 0.5 and Intercept -100 (stored = 2 · value + 200), so
that reading them back needs the modality LUT and gives the NIfTI's values
exactly (for integer samples from -100 to 16000). Positions, orientations and
spacings are decimal strings of the 16 characters DICOM allows (12 to 15
significant digits).

--rotate DEG turns the whole grid by DEG degrees about the oblique axis
(1, 2, 3)/√14 through the centre of the volume: positions and orientations are
rotated, so the series is oblique (no axis along a patient axis).
--syntax chooses the transfer syntax: explicit or implicit VR little endian,
explicit VR big endian, deflated explicit VR little endian, or RLE lossless
(pydicom's own encoder).
--shuffle gives the files random names and shuffles the Instance Numbers, so
that only the positions tell the order.
--enhanced writes one Enhanced CT file instead (PS3.3 C.7.6.16): the frames in
reverse order, each placed by its Plane Position Sequence in the Per-frame
Functional Groups, orientation, pixel measures and rescale in the Shared ones.

Malformed series, for tests of what readers refuse:
--drop-slice K leaves slice K out (a gap); --tilt DEG moves slice k by
k · spacing · tan(DEG) along the column direction (a gantry tilt);
--second-series adds the first three slices again under another Series Instance
UID; --mixed-orientation gives slice 1 an orientation turned by 90° in its plane.

Used as a module, write_series() writes the series and returns its LPS
voxel-to-world affine (4 × 4, index (column, row, slice)) and its Series UID.
"""

from __future__ import annotations

import argparse
import math
import random
from pathlib import Path
from typing import Any, Dict, Optional, Sequence

import nibabel as nib
import numpy as np
from pydicom.dataset import Dataset, FileDataset, FileMetaDataset
from pydicom.filewriter import dcmwrite
from pydicom.valuerep import format_number_as_ds
from pydicom.uid import (
    CTImageStorage,
    DeflatedExplicitVRLittleEndian,
    EnhancedCTImageStorage,
    ExplicitVRBigEndian,
    ExplicitVRLittleEndian,
    ImplicitVRLittleEndian,
    RLELossless,
    generate_uid,
)

SLOPE = 0.5
INTERCEPT = -100.0
SYNTAXES = {
    "explicit": ExplicitVRLittleEndian,
    "implicit": ImplicitVRLittleEndian,
    "big": ExplicitVRBigEndian,
    "deflated": DeflatedExplicitVRLittleEndian,
    "rle": RLELossless,
}
RAS_TO_LPS = np.diag([-1.0, -1.0, 1.0, 1.0])
AXIS = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)



def decimal(value: float) -> str:
    """``value`` as a DICOM decimal string, as precise as its 16 characters allow."""
    return format_number_as_ds(float(value))

def rotation(degrees: float) -> np.ndarray:
    """The 3 × 3 rotation by ``degrees`` about :data:`AXIS` (Rodrigues)."""
    angle = math.radians(degrees)
    k = np.array([[0, -AXIS[2], AXIS[1]], [AXIS[2], 0, -AXIS[0]], [-AXIS[1], AXIS[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def series_affine(nifti_affine: np.ndarray, shape: Sequence[int], rotate: float = 0.0) -> np.ndarray:
    """The LPS voxel-to-world affine of the series written from a NIfTI image with
    ``nifti_affine`` and ``shape``: the affine in LPS, turned by ``rotate`` degrees
    about :data:`AXIS` through the centre of the volume."""
    lps = RAS_TO_LPS @ np.asarray(nifti_affine, dtype=float)
    centre = lps @ np.append((np.asarray(shape[:3], dtype=float) - 1) / 2, 1.0)
    turn = np.eye(4)
    turn[:3, :3] = rotation(rotate)
    turn[:3, 3] = centre[:3] - turn[:3, :3] @ centre[:3]
    return turn @ lps


def slice_dataset(
    plane: np.ndarray,
    position: np.ndarray,
    orientation: np.ndarray,
    spacing: Sequence[float],
    uids: Dict[str, str],
    instance: int,
    syntax: str,
) -> FileDataset:
    """The DICOM data set of one slice: ``plane`` indexed ``[column, row]``."""
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = CTImageStorage
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset("", {}, file_meta=meta, preamble=b"\0" * 128)
    ds.SOPClassUID = CTImageStorage
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.StudyInstanceUID = uids["study"]
    ds.SeriesInstanceUID = uids["series"]
    ds.FrameOfReferenceUID = uids["frame"]
    ds.Modality = "CT"
    ds.PatientName = "Template^MNI152"
    ds.PatientID = "MNI152"
    ds.StudyDate = "20260101"
    ds.StudyTime = "120000"
    ds.StudyID = "1"
    ds.AccessionNumber = ""
    ds.SeriesNumber = 1
    ds.InstanceNumber = instance
    ds.ImagePositionPatient = [decimal(v) for v in position]
    ds.ImageOrientationPatient = [decimal(v) for v in orientation]
    ds.PixelSpacing = [decimal(spacing[1]), decimal(spacing[0])]
    ds.SliceThickness = decimal(spacing[2])
    ds.RescaleSlope = f"{SLOPE:g}"
    ds.RescaleIntercept = f"{INTERCEPT:g}"
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.Rows, ds.Columns = plane.shape[1], plane.shape[0]
    ds.BitsAllocated = 16
    ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 1
    stored = np.rint((plane.T - INTERCEPT) / SLOPE).astype(np.int16)
    ds.PixelData = stored.tobytes()
    if syntax == "rle":
        ds.compress(RLELossless, encoding_plugin="pydicom")
    elif syntax == "big":
        ds.file_meta.TransferSyntaxUID = ExplicitVRBigEndian
        ds.PixelData = stored.astype(">i2").tobytes()
    else:
        ds.file_meta.TransferSyntaxUID = SYNTAXES[syntax]
    return ds


def enhanced_dataset(
    data: np.ndarray,
    positions: Sequence[np.ndarray],
    orientation: np.ndarray,
    spacing: Sequence[float],
    uids: Dict[str, str],
) -> FileDataset:
    """One Enhanced CT data set of the planes ``data[:, :, k]`` at ``positions``,
    stored last plane first."""
    ds = slice_dataset(data[:, :, 0], positions[0], orientation, spacing, uids, 1, "explicit")
    ds.SOPClassUID = ds.file_meta.MediaStorageSOPClassUID = EnhancedCTImageStorage
    for name in ("ImagePositionPatient", "ImageOrientationPatient", "PixelSpacing", "SliceThickness", "RescaleSlope", "RescaleIntercept"):
        delattr(ds, name)
    order = list(reversed(range(data.shape[2])))
    ds.NumberOfFrames = len(order)
    shared = Dataset()
    shared.PlaneOrientationSequence = [Dataset()]
    shared.PlaneOrientationSequence[0].ImageOrientationPatient = [decimal(v) for v in orientation]
    shared.PixelMeasuresSequence = [Dataset()]
    shared.PixelMeasuresSequence[0].PixelSpacing = [decimal(spacing[1]), decimal(spacing[0])]
    shared.PixelMeasuresSequence[0].SliceThickness = decimal(spacing[2])
    shared.PixelValueTransformationSequence = [Dataset()]
    shared.PixelValueTransformationSequence[0].RescaleSlope = f"{SLOPE:g}"
    shared.PixelValueTransformationSequence[0].RescaleIntercept = f"{INTERCEPT:g}"
    shared.PixelValueTransformationSequence[0].RescaleType = "US"
    ds.SharedFunctionalGroupsSequence = [shared]
    frames = []
    for k in order:
        frame = Dataset()
        frame.PlanePositionSequence = [Dataset()]
        frame.PlanePositionSequence[0].ImagePositionPatient = [decimal(v) for v in positions[k]]
        frames.append(frame)
    ds.PerFrameFunctionalGroupsSequence = frames
    stored = np.rint((data[:, :, order].transpose(2, 1, 0) - INTERCEPT) / SLOPE).astype(np.int16)
    ds.PixelData = stored.tobytes()
    return ds


def write_series(
    nifti: Path,
    out: Path,
    syntax: str = "explicit",
    rotate: float = 0.0,
    slices: Optional[Sequence[int]] = None,
    shuffle: bool = False,
    seed: int = 0,
    drop_slice: Optional[int] = None,
    tilt: float = 0.0,
    second_series: bool = False,
    mixed_orientation: bool = False,
    enhanced: bool = False,
) -> Dict[str, Any]:
    """Write the series (see the module's doc); its LPS affine and Series UID."""
    if syntax not in SYNTAXES:
        raise ValueError(f"syntax: one of {', '.join(SYNTAXES)}")
    image = nib.load(str(nifti))
    data = np.asanyarray(image.dataobj).astype(np.float64)
    first, stop = slices if slices is not None else (0, data.shape[2])
    data = data[:, :, first:stop]
    shift = np.eye(4)
    shift[2, 3] = first
    affine = series_affine(image.affine @ shift, data.shape, rotate)
    axes = affine[:3, :3]
    spacing = np.linalg.norm(axes, axis=0)
    row, column = axes[:, 0] / spacing[0], axes[:, 1] / spacing[1]
    orientation = np.concatenate([row, column])
    out.mkdir(parents=True, exist_ok=True)
    rng = random.Random(seed)
    uids = {"study": generate_uid(), "series": generate_uid(), "frame": generate_uid()}
    count = data.shape[2]
    instances = list(range(1, count + 1))
    if shuffle:
        rng.shuffle(instances)
    tilt_step = spacing[2] * math.tan(math.radians(tilt))
    if enhanced:
        positions = [affine[:3, 3] + axes[:, 2] * k for k in range(count)]
        save(enhanced_dataset(data, positions, orientation, spacing, uids), out / "enhanced.dcm", "explicit")
        return {"affine": affine, "series": uids["series"], "files": 1}
    written = []
    for k in range(count):
        if k == drop_slice:
            continue
        position = affine[:3, 3] + axes[:, 2] * k + column * tilt_step * k
        turned = np.concatenate([column, -row]) if mixed_orientation and k == 1 else orientation
        ds = slice_dataset(data[:, :, k], position, turned, spacing, uids, instances[k], syntax)
        name = f"{rng.getrandbits(48):012x}.dcm" if shuffle else f"slice{k:04d}.dcm"
        save(ds, out / name, syntax)
        written.append((data[:, :, k], position, ds))
    if second_series:
        other = dict(uids, series=generate_uid())
        for k, (plane, position, _) in enumerate(written[:3]):
            ds = slice_dataset(plane, position, orientation, spacing, other, k + 1, syntax)
            save(ds, out / f"other{k:04d}.dcm", syntax)
    return {"affine": affine, "series": uids["series"], "files": count - (drop_slice is not None)}


def save(ds: FileDataset, path: Path, syntax: str) -> None:
    """Write ``ds`` in its transfer syntax."""
    if syntax == "big":
        dcmwrite(path, ds, implicit_vr=False, little_endian=False, enforce_file_format=True)
    else:
        ds.save_as(path, enforce_file_format=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("nifti", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--syntax", choices=sorted(SYNTAXES), default="explicit")
    parser.add_argument("--rotate", type=float, default=0.0, metavar="DEG")
    parser.add_argument("--slices", metavar="A:B", help="write the NIfTI's planes A to B-1 only")
    parser.add_argument("--shuffle", action="store_true")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--drop-slice", type=int, metavar="K")
    parser.add_argument("--tilt", type=float, default=0.0, metavar="DEG")
    parser.add_argument("--second-series", action="store_true")
    parser.add_argument("--mixed-orientation", action="store_true")
    parser.add_argument("--enhanced", action="store_true")
    args = parser.parse_args()
    slices = tuple(int(v) for v in args.slices.split(":")) if args.slices else None
    written = write_series(
        args.nifti,
        args.out,
        syntax=args.syntax,
        rotate=args.rotate,
        slices=slices,
        shuffle=args.shuffle,
        seed=args.seed,
        drop_slice=args.drop_slice,
        tilt=args.tilt,
        second_series=args.second_series,
        mixed_orientation=args.mixed_orientation,
        enhanced=args.enhanced,
    )
    print(f"write_dicom_series: {written['files']} slices of series {written['series']} in {args.out}")


if __name__ == "__main__":
    main()
