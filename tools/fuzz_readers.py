#!/usr/bin/env python3
"""Mutation fuzzing of the neuroimaging readers through the release `crestline` tool.

Usage:
    cargo build --release
    tools/fetch_pydicom_data.sh            # DICOM seeds (skipped when absent)
    python3 tools/fuzz_readers.py [--mutants N] [--seed S] [--jobs J]
                                  [--formats NAME,...] [--keep DIR] [--tool PATH]

Small valid files of each format are written (a cube as a GIfTI surface with
ASCII, base64 and gzip-base64 arrays, as a FreeSurfer surface, per-vertex values
as a GIfTI `.shape.gii` and a FreeSurfer curv file) or taken from pydicom's test
data (single DICOM files: native, RLE, JPEG baseline and extended, multi-frame
RLE; a series of four slices written from `MR_small.dcm` with pydicom). Each
mutant changes one to three things: generic byte mutations (bit flips,
interesting bytes and 32-bit words, truncation, duplicated and deleted chunks,
numbers swapped or made huge) or a change aimed at a known way of failing (a
GIfTI `Dim0` beyond memory, a gzip bomb, 200,000 attributes on one element,
deep nesting, an RLE header claiming 0xFFFFFFFF segments or corrupt offsets, a
JPEG frame header claiming 65535 x 65535 pixels). Per-vertex files are given to
`morse --indicator` and `ridges --smoothing-weights` on a cube; surfaces and
DICOM input to `info` (and every fourth surface to `ridges -o`). A pipe named as
each format is tried once per format.

Each run is limited to 4 GiB of address space (`ulimit -v 4194304`) and 20 s.
Counted per format: exit codes (only 0 and 1 are allowed), runs that time out,
stderr lines with `panicked` or an allocation abort, Rust debug text (`Some(`,
`None`, `["`), `--word` that is not one of the tool's options (a library's
backticks turned into a flag), failures without exactly one `error:` line or
whose error does not name the file at fault, outputs left in the output folder
after a failure, and changed inputs. Failing mutants are kept under `--keep`
(default: a temporary folder) with what the tool printed. Exit status 1 when any
problem was found.
"""

from __future__ import annotations

import argparse
import base64
import collections
import concurrent.futures
import hashlib
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence, Tuple

REPO = Path(__file__).resolve().parent.parent
TOOL = REPO / "target" / "release" / "crestline"
PYDICOM_DATA = REPO / "data" / "dicom" / "pydicom"
TIMEOUT = 20.0
LIMITED = 'ulimit -v 4194304; exec "$0" "$@"'

# A cube: 8 vertices, 12 triangles, counter-clockwise seen from outside.
VERTICES = [(0, 0, 0), (1.5, 0, 0), (1.5, 1.5, 0), (0, 1.5, 0),
            (0, 0, -1.25), (1.5, 0, -1.25), (1.5, 1.5, -1.25), (0, 1.5, -1.25)]
QUADS = [(0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]
TRIANGLES = [t for a, b, c, d in QUADS for t in ((a, b, c), (a, c, d))]
VALUES = [0.5, 1.25, 3.0, 0.0, 0.125, 7.5, 2.0, 4.25]  # valid weights and indicators

# ---------------------------------------------------------------------------
# Seed files


def cube_obj() -> bytes:
    lines = [f"v {x} {y} {z}" for x, y, z in VERTICES]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in TRIANGLES]
    return ("\n".join(lines) + "\n").encode()


def gifti_array(intent: str, dtype: str, dims: Sequence[int], encoding: str, data: str) -> str:
    dim_attributes = "".join(f' Dim{i}="{d}"' for i, d in enumerate(dims))
    return (f'<DataArray Intent="{intent}" DataType="{dtype}" ArrayIndexingOrder="RowMajorOrder" '
            f'Dimensionality="{len(dims)}"{dim_attributes} Encoding="{encoding}" '
            f'Endian="LittleEndian" ExternalFileName="" ExternalFileOffset="">\n'
            f'<MetaData><MD><Name><![CDATA[Name]]></Name><Value><![CDATA[cube]]></Value></MD>'
            f'</MetaData>\n<Data>{data}</Data></DataArray>\n')


def gifti(arrays: str) -> bytes:
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<!DOCTYPE GIFTI SYSTEM "http://www.nitrc.org/frs/download.php/115/gifti.dtd">\n'
            f'<GIFTI Version="1.0" NumberOfDataArrays="2">\n{arrays}</GIFTI>\n').encode()


def encoded(raw: bytes, encoding: str) -> str:
    if encoding == "Base64Binary":
        return base64.b64encode(raw).decode()
    return base64.b64encode(zlib.compress(raw)).decode()


def gifti_surface(encoding: str) -> bytes:
    points = [c for v in VERTICES for c in v]
    corners = [c for t in TRIANGLES for c in t]
    if encoding == "ASCII":
        pdata = " ".join(str(float(c)) for c in points)
        tdata = " ".join(str(c) for c in corners)
    else:
        pdata = encoded(struct.pack(f"<{len(points)}f", *points), encoding)
        tdata = encoded(struct.pack(f"<{len(corners)}i", *corners), encoding)
    return gifti(gifti_array("NIFTI_INTENT_POINTSET", "NIFTI_TYPE_FLOAT32", [8, 3], encoding, pdata)
                 + gifti_array("NIFTI_INTENT_TRIANGLE", "NIFTI_TYPE_INT32", [12, 3], encoding, tdata))


def gifti_values() -> bytes:
    data = encoded(struct.pack("<8f", *VALUES), "GZipBase64Binary")
    return gifti(gifti_array("NIFTI_INTENT_SHAPE", "NIFTI_TYPE_FLOAT32", [8], "GZipBase64Binary", data))


def freesurfer_surface() -> bytes:
    out = b"\xff\xff\xfe" + b"created by fuzz_readers\n\n" + struct.pack(">ii", 8, 12)
    out += b"".join(struct.pack(">3f", *v) for v in VERTICES)
    out += b"".join(struct.pack(">3i", *t) for t in TRIANGLES)
    return out


def curv() -> bytes:
    return b"\xff\xff\xff" + struct.pack(">iii", 8, 12, 1) + struct.pack(">8f", *VALUES)


def dicom_series(folder: Path) -> Optional[List[bytes]]:
    """Four slices of `MR_small.dcm` 1 mm apart, as one series, the last two
    RLE-compressed (needs pydicom and numpy)."""
    source = PYDICOM_DATA / "MR_small.dcm"
    try:
        import pydicom
        from pydicom.uid import RLELossless, generate_uid
    except ImportError:
        return None
    if not source.is_file():
        return None
    series_uid = generate_uid()
    files = []
    for k in range(4):
        ds = pydicom.dcmread(source)
        ds.SeriesInstanceUID = series_uid
        ds.SOPInstanceUID = generate_uid()
        ds.file_meta.MediaStorageSOPInstanceUID = ds.SOPInstanceUID
        ds.InstanceNumber = k + 1
        ds.ImagePositionPatient = [-83.9063, -91.2, 6.6406 + k]
        ds.SliceThickness = 1.0
        if k >= 2:
            ds.compress(RLELossless)
        path = folder / f"slice{k}.dcm"
        ds.save_as(path, enforce_file_format=True)
        files.append(path.read_bytes())
    return files


def dicom_jpeg(folder: Path) -> Optional[bytes]:
    """`MR_small.dcm` as 8-bit baseline JPEG, which jpeg-decoder decodes (pydicom's
    own JPEG files store 12 bits; needs pydicom, numpy and Pillow)."""
    source = PYDICOM_DATA / "MR_small.dcm"
    try:
        import io

        import numpy as np
        import pydicom
        from PIL import Image
        from pydicom.encaps import encapsulate
        from pydicom.uid import JPEGBaseline8Bit
    except ImportError:
        return None
    if not source.is_file():
        return None
    ds = pydicom.dcmread(source)
    pixels = ds.pixel_array.astype(np.float64)
    scaled = (255 * (pixels - pixels.min()) / max(np.ptp(pixels), 1)).astype(np.uint8)
    jpeg = io.BytesIO()
    Image.fromarray(scaled).save(jpeg, format="JPEG", quality=90)
    ds.PixelData = encapsulate([jpeg.getvalue()])
    ds["PixelData"].VR = "OB"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 8, 8, 7, 0
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.file_meta.TransferSyntaxUID = JPEGBaseline8Bit
    path = folder / "jpeg.dcm"
    ds.save_as(path, enforce_file_format=True)
    return path.read_bytes()


# ---------------------------------------------------------------------------
# Mutations

INTERESTING_BYTES = [0, 0xFF, ord("-"), ord("9"), ord("e"), ord("\n"), ord(" "), ord("."), 0x7F, 0x80, 0x07, 0x1B]
HUGE_NUMBERS = [b"0", b"-1", b"2147483648", b"4294967295", b"4294967296", b"1000000000000000",
                b"18446744073709551615", b"99999999999999999999999", b"1e308", b"nan"]
WORDS = [0, 1, 2, 3, 0x7F, 0xFF, 0x100, 0xFFFF, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 0x40000000,
         0x7F800000, 0x7FC00000]


def byte_mutation(data: bytearray, rng: random.Random) -> str:
    if not data:
        return "empty"
    kind = rng.choice(["flip", "byte", "truncate", "duplicate", "delete", "number", "word"])
    at = rng.randrange(len(data))
    if kind == "flip":
        data[at] ^= 1 << rng.randrange(8)
    elif kind == "byte":
        data[at] = rng.choice(INTERESTING_BYTES)
    elif kind == "truncate":
        del data[at:]
    elif kind in ("duplicate", "delete"):
        end = min(len(data), at + 1 + rng.randrange(64))
        if kind == "duplicate":
            data[at:at] = data[at:end]
        else:
            del data[at:end]
    elif kind == "number":
        runs = [m.span() for m in re.finditer(rb"[0-9]+", bytes(data))]
        if runs:
            start, end = rng.choice(runs)
            data[start:end] = rng.choice(HUGE_NUMBERS)
    elif len(data) >= 4:
        at = rng.randrange(len(data) - 3)
        data[at:at + 4] = struct.pack(rng.choice("<>") + "I", rng.choice(WORDS))
    return kind


def set_attribute(data: bytearray, rng: random.Random) -> str:
    """A GIfTI attribute given a hostile value."""
    choices = {
        b"Dim0": [b"1100000000", b"-3", b"0", b"18446744073709551615", b"89478485"],
        b"Dim1": [b"0", b"4", b"1000000000"],
        b"Dimensionality": [b"0", b"7", b"3"],
        b"DataType": [b"NIFTI_TYPE_UINT8", b"NIFTI_TYPE_FLOAT64", b"NIFTI_TYPE_INT32", b"x"],
        b"Encoding": [b"ASCII", b"Base64Binary", b"GZipBase64Binary", b"ExternalFileBinary"],
        b"Endian": [b"BigEndian", b"Middle"],
        b"Intent": [b"NIFTI_INTENT_TRIANGLE", b"NIFTI_INTENT_POINTSET", b"NIFTI_INTENT_NONE"],
        b"ArrayIndexingOrder": [b"ColumnMajorOrder", b"Diagonal"],
    }
    name = rng.choice(list(choices))
    spots = [m.span(1) for m in re.finditer(name + rb'="([^"]*)"', bytes(data))]
    if not spots:
        return "attribute"
    start, end = rng.choice(spots)
    data[start:end] = rng.choice(choices[name])
    return f"attribute {name.decode()}"


BOMB_BYTES = 1 << 30
_bomb: List[bytes] = []


def bomb_payload() -> bytes:
    """1 GiB of zeros, zlib-compressed (1 MB) and base64-encoded (1.4 MB), made once."""
    if not _bomb:
        compressor = zlib.compressobj(9)
        chunk = bytes(1 << 20)
        parts = [compressor.compress(chunk) for _ in range(BOMB_BYTES >> 20)]
        _bomb.append(base64.b64encode(b"".join(parts) + compressor.flush()))
    return _bomb[0]


def gzip_bomb(data: bytearray, rng: random.Random) -> str:
    """The first array replaced by 1 GiB of zeros, its dimensions matching (an
    N x 3 array stays one) or one number short."""
    text = bytes(data)
    rows = re.search(rb'Dim1="3"', text.split(b"</DataArray>")[0]) is not None
    count = BOMB_BYTES // (12 if rows else 4) - (0 if rng.random() < 0.5 else 1)
    dims = b'Dimensionality="2" Dim0="%d" Dim1="3"' % count if rows else b'Dimensionality="1" Dim0="%d"' % count
    text = re.sub(rb'Dimensionality="\d+" Dim0="\d+"( Dim1="\d+")?', dims, text, count=1)
    text = re.sub(rb'Encoding="[A-Za-z0-9]+"', b'Encoding="GZipBase64Binary"', text, count=1)
    text = re.sub(rb"<Data>[^<]*</Data>", b"<Data>" + bomb_payload() + b"</Data>", text, count=1)
    data[:] = text
    return "gzip bomb"


def many_attributes(data: bytearray, rng: random.Random) -> str:
    attributes = b"".join(b' a%d="%d"' % (i, i) for i in range(200_000))
    at = bytes(data).find(b"<GIFTI")
    if at >= 0:
        data[at + 6:at + 6] = attributes
    return "200,000 attributes"


def deep_nesting(data: bytearray, rng: random.Random) -> str:
    at = bytes(data).find(b"</GIFTI>")
    if at >= 0:
        data[at:at] = b"<a>" * 100_000 + b"</a>" * 100_000
    return "deep nesting"


def rle_header(data: bytearray, rng: random.Random) -> str:
    at = bytes(data).find(b"\x02\x00\x00\x00\x40\x00\x00\x00")
    if at < 0:
        at = bytes(data).find(b"\x01\x00\x00\x00\x40\x00\x00\x00")
    if at < 0:
        return "rle header (none)"
    field = rng.choice([0, 4, 8])
    data[at + field:at + field + 4] = struct.pack("<I", rng.choice([0xFFFFFFFF, 0, 15, 16, 63, 65, 0x7FFFFFFF, 200]))
    return f"rle header +{field}"


def jpeg_frame(data: bytearray, rng: random.Random) -> str:
    text = bytes(data)
    start = text.find(b"\xff\xd8\xff")
    sof = -1 if start < 0 else next((i for i in range(start, len(text) - 9)
                                     if text[i] == 0xFF and text[i + 1] in (0xC0, 0xC1, 0xC3)), -1)
    if sof < 0:
        return "jpeg frame (none)"
    data[sof + 5:sof + 9] = struct.pack(">HH", rng.choice([65535, 0, 1]), rng.choice([65535, 0, 1]))
    if rng.random() < 0.5:
        data[sof + 4] = 8  # a precision jpeg-decoder decodes (pydicom's JPEG files have 12)
        return "jpeg frame size, 8 bits"
    return "jpeg frame size"


def curv_count(data: bytearray, rng: random.Random) -> str:
    field = rng.choice([3, 7, 11])
    data[field:field + 4] = struct.pack(">I", rng.choice(WORDS))
    return f"curv count +{field}"


TARGETED: Dict[str, List[Tuple[Callable[[bytearray, random.Random], str], float]]] = {
    "gifti": [(set_attribute, 0.25), (gzip_bomb, 0.01), (many_attributes, 0.004), (deep_nesting, 0.004)],
    "dicom": [(rle_header, 0.1), (jpeg_frame, 0.1)],
    "curv": [(curv_count, 0.2)],
    "surf": [(curv_count, 0.2)],
}


def mutate(seed: bytes, family: str, rng: random.Random) -> Tuple[bytes, List[str]]:
    data = bytearray(seed)
    applied = []
    for _ in range(1 + rng.randrange(3)):
        for mutation, rate in TARGETED.get(family, []):
            if rng.random() < rate:
                applied.append(mutation(data, rng))
                break
        else:
            applied.append(byte_mutation(data, rng))
    return bytes(data), applied


# ---------------------------------------------------------------------------
# Formats


class Format:
    """A seed of one format, the tool's command on a mutant, and the file at fault."""

    def __init__(self, name: str, family: str, file_name: str, seeds: List[bytes],
                 commands: Callable[[Path, Path, Path, int], List[List[str]]]):
        self.name, self.family, self.file_name = name, family, file_name
        self.seeds, self.commands = seeds, commands
        # A name for folders: the format's words joined.
        self.slug = "-".join(re.findall(r"[a-z0-9]+", name.lower()))


def surface_commands(path: Path, out: Path, mesh: Path, index: int) -> List[List[str]]:
    runs = [["info", str(path)]]
    if index % 4 == 0:
        runs.append(["ridges", str(path), "-o", str(out / "out.ply")])
    return runs


def values_commands(path: Path, out: Path, mesh: Path, index: int) -> List[List[str]]:
    if index % 2 == 0:
        return [["morse", str(mesh), "--indicator", str(path), "-o", str(out / "out.ply")]]
    return [["ridges", str(mesh), "--smoothing-weights", str(path), "-o", str(out / "out.ply")]]


def info_command(path: Path, out: Path, mesh: Path, index: int) -> List[List[str]]:
    return [["info", str(path)]]


def formats(work: Path) -> List[Format]:
    found = [Format("GIfTI surface (ASCII)", "gifti", "m.surf.gii", [gifti_surface("ASCII")], surface_commands),
             Format("GIfTI surface (base64)", "gifti", "m.surf.gii", [gifti_surface("Base64Binary")], surface_commands),
             Format("GIfTI surface (gzip base64)", "gifti", "m.surf.gii", [gifti_surface("GZipBase64Binary")],
                    surface_commands),
             Format("GIfTI per-vertex values", "gifti", "v.shape.gii", [gifti_values()], values_commands),
             Format("FreeSurfer surface", "surf", "lh.cube", [freesurfer_surface()], surface_commands),
             Format("FreeSurfer curv", "curv", "lh.curv", [curv()], values_commands)]
    names = ["MR_small.dcm", "MR_small_RLE.dcm", "JPGExtended.dcm", "JPEG-lossy.dcm", "rtdose_rle.dcm", "CT_small.dcm"]
    dicom = [(PYDICOM_DATA / n).read_bytes() for n in names if (PYDICOM_DATA / n).is_file()]
    series_dir = work / "series-seed"
    series_dir.mkdir()
    jpeg = dicom_jpeg(series_dir)
    if jpeg:
        # Twice: two of the seven seeds decode as JPEG.
        dicom += [jpeg, jpeg]
    if dicom:
        found.append(Format("DICOM file", "dicom", "f.dcm", dicom, info_command))
    else:
        print(f"skipped: DICOM files (run tools/fetch_pydicom_data.sh)", file=sys.stderr)
    series = dicom_series(series_dir)
    if series:
        found.append(Format("DICOM series", "dicom", "series", series, info_command))
    else:
        print("skipped: DICOM series (needs pydicom and tools/fetch_pydicom_data.sh)", file=sys.stderr)
    return found


# ---------------------------------------------------------------------------
# Running and judging


def option_names() -> set:
    names = set()
    for command in ["", "info", "ridges", "morse", "iso"]:
        text = subprocess.run([str(TOOL)] + ([command] if command else []) + ["--help"],
                              capture_output=True, text=True).stdout
        names.update(re.findall(r"--([a-z][a-z0-9-]*)", text))
    return names


def digest(paths: Sequence[Path]) -> str:
    h = hashlib.sha256()
    for path in paths:
        h.update(path.read_bytes() if path.is_file() else b"-")
    return h.hexdigest()


def judge(code: Optional[int], err: str, faulty: Sequence[str], out_dir: Path, options: set) -> List[str]:
    """The problems of one run: `faulty` are the names an error may give."""
    problems = []
    if code is None:
        return ["timeout"]
    if code not in (0, 1):
        problems.append(f"exit {code}")
    lines = err.splitlines()
    if any("panicked" in line or "memory allocation of" in line for line in lines):
        problems.append("panic text")
    if re.search(r"Some\(|\bNone\b|\[\"", err):
        problems.append("debug text")
    # Input text an error quotes ('...') may hold anything a mutant holds.
    unquoted = re.sub(r"'[^'\n]*'", "''", err)
    unknown = [w for w in re.findall(r"(?<![\w-])--([A-Za-z0-9_][\w-]*)", unquoted) if w not in options]
    if unknown:
        problems.append("backtick as --")
    if code == 1:
        errors = [line for line in lines if line.startswith("error:")]
        others = [line for line in lines if not line.startswith(("error:", "warning:"))]
        if len(errors) != 1 or others:
            problems.append("not one error line")
        elif not any(name in errors[0] for name in faulty):
            problems.append("error names another file")
        left = [p.name for p in out_dir.iterdir()]
        if left:
            problems.append("output left behind")
    elif code == 0 and any(p.name.startswith(".crestline") for p in out_dir.iterdir()):
        problems.append("temporary file left behind")
    return problems


def run_tool(args: List[str], cwd: Path) -> Tuple[Optional[int], str]:
    try:
        done = subprocess.run(["sh", "-c", LIMITED, str(TOOL)] + args, cwd=cwd, capture_output=True,
                              timeout=TIMEOUT, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return None, ""
    return done.returncode, done.stderr.decode(errors="replace")


def run_mutant(fmt: Format, index: int, rng_seed: int, work: Path, mesh: Path, options: set,
               keep: Path) -> Tuple[str, Dict[str, int], List[str]]:
    rng = random.Random(rng_seed)
    case = work / f"{fmt.slug}-{index}"
    case.mkdir()
    out = case / "out"
    out.mkdir()
    if fmt.name == "DICOM series":
        target = case / "series"
        target.mkdir()
        for k, seed in enumerate(fmt.seeds):
            (target / f"slice{k}.dcm").write_bytes(seed)
        changed = rng.sample(range(len(fmt.seeds)), 1 + rng.randrange(2))
        applied = []
        for k in changed:
            data, what = mutate(fmt.seeds[k], fmt.family, rng)
            (target / f"slice{k}.dcm").write_bytes(data)
            applied += [f"slice{k}: {w}" for w in what]
        inputs = sorted(target.iterdir())
        faulty = [str(target)] + [str(p) for p in inputs]
    else:
        target = case / fmt.file_name
        data, applied = mutate(rng.choice(fmt.seeds), fmt.family, rng)
        target.write_bytes(data)
        inputs = [target]
        faulty = [str(target)]
    before = digest(inputs + [mesh])
    tally: Dict[str, int] = collections.Counter()
    problems: List[str] = []
    for args in fmt.commands(target, out, mesh, index):
        code, err = run_tool(args, case)
        tally["runs"] += 1
        tally[f"exit {code}" if code is not None else "timeout"] += 1
        tally["panic lines"] += sum("panicked" in line for line in err.splitlines())
        for note, text in NOTED.items():
            tally[note] += text in err
        found = judge(code, err, faulty, out, options)
        for problem in found:
            tally[problem] += 1
        if found:
            problems.append(f"{fmt.name} mutant {index} {applied}: {found}: crestline {' '.join(args)}\n{err}")
            kept = keep / f"{fmt.slug}-{index}"
            shutil.copytree(case, kept, dirs_exist_ok=True)
            (kept / "stderr.txt").write_text(err)
        for p in out.iterdir():
            if p.is_dir():
                shutil.rmtree(p)
            else:
                p.unlink()
    if digest(inputs + [mesh]) != before:
        tally["inputs changed"] += 1
    shutil.rmtree(case, ignore_errors=True)
    return fmt.name, tally, problems


def check_seeds(fmt: Format, work: Path, mesh: Path) -> List[str]:
    """The seed files of `fmt` the tool does not read (a broken seed fuzzes nothing)."""
    failed = []
    for k, seed in enumerate(fmt.seeds):
        case = work / f"{fmt.slug}-seed{k}"
        out = case / "out"
        out.mkdir(parents=True)
        if fmt.name == "DICOM series":
            target = case / "series"
            target.mkdir()
            for i, data in enumerate(fmt.seeds):
                (target / f"slice{i}.dcm").write_bytes(data)
        else:
            target = case / fmt.file_name
            target.write_bytes(seed)
        for args in fmt.commands(target, out, mesh, 0):
            code, err = run_tool(args, case)
            if code != 0:
                failed.append(f"{fmt.name} seed {k}: crestline {' '.join(args)}: {err.strip()}")
        shutil.rmtree(case)
        if fmt.name == "DICOM series":
            break
    return failed


def pipe_runs(fmt: Format, work: Path, mesh: Path, options: set) -> Tuple[Dict[str, int], List[str]]:
    """The format's commands on a FIFO named as its files."""
    case = work / f"{fmt.slug}-pipe"
    case.mkdir(exist_ok=True)
    out = case / "out"
    out.mkdir(exist_ok=True)
    target = case / (fmt.file_name if fmt.name != "DICOM series" else "DICOMDIR")
    os.mkfifo(target)
    tally: Dict[str, int] = collections.Counter()
    problems = []
    for args in fmt.commands(target, out, mesh, 0):
        code, err = run_tool(args, case)
        tally["pipe runs"] += 1
        for note, text in NOTED.items():
            tally[note] += text in err
        found = judge(code, err, [str(target), str(mesh)], out, options)
        for problem in found:
            tally[f"pipe: {problem}"] += 1
        if found:
            problems.append(f"{fmt.name} pipe: {found}: crestline {' '.join(args)}\n{err}")
    return tally, problems


# Errors counted by kind (not problems): a decoder's panic caught and reported,
# memory refused, a pipe refused.
NOTED = {"caught decoder panic": "the decoder stopped on corrupt data",
         "memory refused": "more than can be allocated",
         "not a regular file": "not a regular file"}

COLUMNS = ["runs", "exit 0", "exit 1", "timeout", "panic lines", "debug text", "backtick as --",
           "not one error line", "error names another file", "output left behind", "inputs changed"]


def main() -> int:
    global TOOL
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mutants", type=int, default=300, help="mutants per format (default 300)")
    parser.add_argument("--seed", type=int, default=57, help="random seed")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time")
    parser.add_argument("--formats", default="", help="comma-separated words a format's name must contain")
    parser.add_argument("--keep", type=Path, default=None, help="folder for failing mutants")
    parser.add_argument("--tool", type=Path, default=TOOL, help=f"the binary (default {TOOL})")
    args = parser.parse_args()
    TOOL = args.tool.resolve()
    if not TOOL.is_file():
        print(f"error: {TOOL} is missing; run cargo build --release", file=sys.stderr)
        return 2
    work = Path(tempfile.mkdtemp(prefix="crestline-fuzz-readers-"))
    keep = args.keep or work / "failures"
    keep.mkdir(parents=True, exist_ok=True)
    mesh = work / "cube.obj"
    mesh.write_bytes(cube_obj())
    options = option_names()
    chosen = [f for f in formats(work)
              if not args.formats or any(w.lower() in f.name.lower() for w in args.formats.split(","))]
    tallies: Dict[str, collections.Counter] = {f.name: collections.Counter() for f in chosen}
    problems: List[str] = []
    broken = [problem for fmt in chosen for problem in check_seeds(fmt, work, mesh)]
    for problem in broken:
        print(f"seed not read (its mutants are still run): {problem}")
    for fmt in chosen:
        tally, found = pipe_runs(fmt, work, mesh, options)
        tallies[fmt.name].update(tally)
        problems += found
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        jobs = [pool.submit(run_mutant, fmt, i, args.seed * 1_000_003 + k * 100_003 + i, work, mesh, options, keep)
                for k, fmt in enumerate(chosen) for i in range(args.mutants)]
        for job in concurrent.futures.as_completed(jobs):
            name, tally, found = job.result()
            tallies[name].update(tally)
            tallies[name]["mutants"] += 1
            problems += found
    print(f"fuzz_readers: seed {args.seed}, {args.mutants} mutants per format, "
          f"ulimit -v 4194304, timeout {TIMEOUT:.0f} s")
    print(f"{'format':<30}{'mutants':>8}" + "".join(f"{c:>{max(8, len(c) + 1)}}" for c in COLUMNS))
    for name, t in tallies.items():
        print(f"{name:<30}{t['mutants']:>8}" + "".join(f"{t[c]:>{max(8, len(c) + 1)}}" for c in COLUMNS))
        extra = {k: v for k, v in t.items() if k not in COLUMNS and k != "mutants"}
        if extra:
            print(f"{'':<30}{dict(sorted(extra.items()))}")
    for problem in problems[:20]:
        print(problem)
    print(f"{len(problems)} problems; failing mutants kept in {keep}")
    shutil.rmtree(work / "series-seed", ignore_errors=True)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
