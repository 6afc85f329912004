#!/usr/bin/env bash
# Fetch the small DICOM files that ship in pydicom's test data into
# data/dicom/pydicom/ at the repository root.
#
# They come from the pydicom wheel on PyPI (version 3.0.2), which holds them under
# pydicom/data/test_files/: one 64×64 MR slice in every transfer syntax pydicom
# tests (explicit and implicit VR little endian, big endian, RLE, JPEG-LS, JPEG
# 2000) and a truncated copy, a CT slice with a rescale to Hounsfield units, 12-bit
# JPEG extended images, a deflated image, multi-frame RT dose grids (native and
# RLE) and the DICOMDIR of a small media folder (without the files it lists). data/ is git-ignored: the files
# are never committed.
#
# Usage: tools/fetch_pydicom_data.sh
# Running it again does nothing when every file is already there.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/dicom/pydicom"
# shellcheck source=tools/wheel_data.sh
source "$repo_root/tools/wheel_data.sh"
readonly FILES=(
    MR_small.dcm
    MR_small_implicit.dcm
    MR_small_bigendian.dcm
    MR_small_expb.dcm
    MR_small_RLE.dcm
    MR_small_jpeg_ls_lossless.dcm
    MR_small_jp2klossless.dcm
    MR_truncated.dcm
    CT_small.dcm
    JPEG-lossy.dcm
    JPGExtended.dcm
    image_dfl.dcm
    rtdose.dcm
    rtdose_rle.dcm
    dicomdirtests/TINY_ALPHA/DICOMDIR
)

fetch_wheel_files fetch_pydicom_data pydicom 3.0.2 pydicom/data/test_files "$DEST" "${FILES[@]}"
