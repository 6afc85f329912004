"""Cohort runs: one task per scan on a Dask cluster, resumable, failures isolated.

    >>> import crestline.cohort
    >>> rows = crestline.cohort.run(["a.nii.gz", "b.nii.gz"], "out", task="landmarks",
    ...                             options={"level": 60})

In a script, call :func:`run` under ``if __name__ == "__main__":``: the worker
processes of a local cluster import the script again.

Every input gets a folder ``out_dir/<subject>/`` with its outputs and a
``manifest.json`` written last: the input's SHA-256, the task, its options, the
outputs, counts and seconds. A rerun skips the subjects whose manifest matches
(same input, task and options, every output present), so an interrupted cohort
continues where it stopped. Outputs are written under temporary names and renamed;
a subject without a manifest is recomputed from an empty folder.

A scan that cannot be read or processed gives a row with ``status="error"`` and the
message, naming the file; the others go on. A worker process that dies is replaced
and its task rescheduled by Dask, up to ``distributed.scheduler.allowed-failures``
times (3 by default); after that the row is an error too.

Memory: crest lines of a 256³ image (and so ``landmarks`` of images) peak at about
2.4 GiB per task, isosurfaces at a few hundred MiB. With ``client=None`` a
LocalCluster of one single-threaded worker process per core is started, fewer if
the machine's memory divided by 3 GiB is smaller, and each worker gets an equal
share of the memory.

Tasks and their options (those of the command-line tool, as keyword arguments of
the package's functions):

- ``landmarks``: images (``level`` required, ``sigma``, ``min_length``) or meshes
  (``estimator``, ``smooth_steps``, ``smooth_time``, ``threshold``), then
  ``radius`` and ``persistence`` (the library's defaults, in voxels or mean edge
  lengths, when not given): ``landmarks.csv`` (id, kind, x, y, z, curvature, line,
  space, as the command-line tool writes it) and ``lines.json``;
- ``ridges`` (meshes), ``crest_lines`` (images; ``level`` required): ``lines.json``;
- ``isosurface`` (images; ``level`` required): ``surface.ply``;
- ``curvature`` (meshes; ``estimator``): ``curvature.ply`` with k_max, k_min;
- ``transfer``: a template's labelled landmarks carried onto every scan
  (:func:`crestline.transfer`), the options ``template`` (an image, with
  ``level``, or a mesh, as the scans are) and ``landmarks`` (its landmarks file)
  given once, and the transfer's own (``scales``, ``iterations``, ...; ``space``
  for meshes): ``landmarks.csv`` (label, x, y, z, confidence, flagged, space:
  RAS, as the command-line tool writes it) and ``landmarks.mrk.json`` (3D Slicer). The
  template's lines are computed once per run, into ``out_dir/template.lines.json``.

The summary is ``out_dir/summary.csv`` (and ``summary.parquet`` when pyarrow is
installed); for ``landmarks`` also ``out_dir/landmarks.csv`` (and ``.parquet``),
every landmark of every subject with a ``subject`` column; for ``transfer``
``out_dir/transferred.csv`` (and ``.parquet``), the long table ``subject, label,
x, y, z, confidence`` (RAS, mm) that R's geomorph and Python's morphops read, with
a last column ``flagged`` (``true`` for a landmark whose part the subject lacks).
"""

import argparse
import csv
import hashlib
import json
import multiprocessing
import os
import shutil
import sys
import time
import uuid
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union


from . import _crestline
from ._built import Mesh
from ._jobs import DEFAULTS
from ._lines import Lines
from ._jobs import options as job_options
from ._mesh import curvature, read_mesh, ridges, write_mesh
from ._transfer import scan_lines, transfer
from ._volume import crest_lines, isosurface, landmarks, read_volume, write_landmarks

PathLike = Union[str, "os.PathLike[str]"]
TASKS = ("landmarks", "ridges", "crest_lines", "isosurface", "curvature", "transfer")
IMAGE_SUFFIXES = (".nii", ".nii.gz", ".nrrd", ".nhdr", ".mha", ".mhd")
MESH_SUFFIXES = (".obj", ".ply", ".off", ".stl")
TASK_PEAK_BYTES = 3 * 2**30
"""What one task may use at most, for the default number of workers: a 256³
image's crest lines peak at about 2.4 GiB."""

SUMMARY_COLUMNS = ("subject", "path", "status", "error", "points", "lines", "seconds", "reused", "outputs")


def subject_of(path: PathLike) -> str:
    """The file name without its extension (both of ``.nii.gz``)."""
    name = Path(path).name
    for suffix in sorted(IMAGE_SUFFIXES + MESH_SUFFIXES, key=len, reverse=True):
        if name.lower().endswith(suffix):
            return name[: -len(suffix)]
    return Path(name).stem


def _option_value(text: str) -> Any:
    """A CSV cell or command-line value as an int, float or string."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def read_inputs(inputs: Union[PathLike, Sequence[PathLike]]) -> List[Tuple[str, str, Dict[str, Any]]]:
    """``(subject, path, options)`` of every input: paths, or a CSV file with a
    ``path`` column, an optional ``subject`` column and per-subject options in the
    other columns (relative paths are taken from the CSV's folder)."""
    if isinstance(inputs, (str, os.PathLike)) and str(inputs).lower().endswith(".csv"):
        table = Path(inputs)
        with open(table, newline="") as f:
            rows = list(csv.DictReader(f))
        if rows and "path" not in rows[0]:
            raise ValueError(f"inputs: {table} has no 'path' column")
        found = []
        for row in rows:
            path = Path(row.pop("path"))
            path = path if path.is_absolute() else table.parent / path
            subject = row.pop("subject", None) or subject_of(path)
            found.append((subject, str(path), {k: _option_value(v) for k, v in row.items() if v != ""}))
    elif isinstance(inputs, (str, os.PathLike)):
        found = [(subject_of(inputs), str(inputs), {})]
    else:
        found = [(subject_of(p), str(p), {}) for p in inputs]
    seen: Dict[str, str] = {}
    for subject, path, _ in found:
        if subject in seen:
            raise ValueError(f"inputs: {seen[subject]} and {path} would both be subject {subject!r}")
        seen[subject] = path
    return found


def sha256(path: PathLike) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _write_atomically(path: Path, write: Callable[[Path], None]) -> None:
    """``write`` to a temporary name beside ``path``, then rename it."""
    partial = path.with_name(f".{path.name}.partial")
    write(partial)
    os.replace(partial, path)


def _is_image(path: str) -> bool:
    return path.lower().endswith(IMAGE_SUFFIXES)


def _image_lines(path: str, options: Dict[str, Any]) -> Tuple[Lines, float]:
    """Crest lines of an image and its voxel size."""
    if "level" not in options:
        raise ValueError("the option 'level' (the isosurface's value) is needed for images")
    image = read_volume(path)
    # The library's options of the job, and the value of a Gaussian curvature kind.
    keys = {"level", "gauss", *DEFAULTS["crest_lines"]}
    found = crest_lines(image, **{k: v for k, v in options.items() if k in keys})
    return found, image.voxel


def _mesh_lines(path: str, options: Dict[str, Any]) -> Tuple[Lines, float]:
    """Ridges and valleys of a mesh and its mean edge length."""
    mesh = Mesh(*read_mesh(path)[:2])
    keys = set(DEFAULTS["ridges"])
    found = ridges(mesh, **{k: v for k, v in options.items() if k in keys})
    return found, mesh.mean_edge_length()


def _save_lines(lines: Lines, folder: Path) -> Tuple[Dict[str, int], List[str]]:
    lines.save(folder / "lines.json")
    return {"lines": len(lines), "points": sum(len(line) for line in lines)}, ["lines.json"]


def _task_landmarks(path: str, options: Dict[str, Any], folder: Path) -> Tuple[Dict[str, int], List[str]]:
    lines, scale = _image_lines(path, options) if _is_image(path) else _mesh_lines(path, options)
    found = landmarks(lines, unit=scale, radius=options.get("radius"), persistence=options.get("persistence"))
    points = found["points"]
    write_landmarks(folder / "landmarks.csv", found)
    counts, outputs = _save_lines(lines, folder)
    return {"points": len(points["kind"]), "lines": counts["lines"]}, ["landmarks.csv", *outputs]


def _task_ridges(path: str, options: Dict[str, Any], folder: Path) -> Tuple[Dict[str, int], List[str]]:
    return _save_lines(_mesh_lines(path, options)[0], folder)


def _task_crest_lines(path: str, options: Dict[str, Any], folder: Path) -> Tuple[Dict[str, int], List[str]]:
    return _save_lines(_image_lines(path, options)[0], folder)


def _task_isosurface(path: str, options: Dict[str, Any], folder: Path) -> Tuple[Dict[str, int], List[str]]:
    if "level" not in options:
        raise ValueError("the option 'level' (the isosurface's value) is needed")
    image = read_volume(path)
    vertices, faces = isosurface(image, options["level"], sigma=options.get("sigma"))
    write_mesh(folder / "surface.ply", vertices, faces, space=image.space)
    return {"points": len(vertices), "lines": 0}, ["surface.ply"]


def _task_curvature(path: str, options: Dict[str, Any], folder: Path) -> Tuple[Dict[str, int], List[str]]:
    vertices, faces, _ = read_mesh(path)
    field = curvature(vertices, faces, estimator=options.get("estimator"))
    write_mesh(folder / "curvature.ply", vertices, faces, {"k_max": field["k_max"], "k_min": field["k_min"]})
    return {"points": len(vertices), "lines": 0}, ["curvature.ply"]


def _transfer_options(options: Dict[str, Any]) -> Dict[str, Any]:
    """The options of the transfer job among ``options`` (the lists ``scales`` and
    ``inner_levels`` also as comma-separated text, as ``--option scales=24,16``
    gives it)."""
    found = {k: v for k, v in options.items() if k in DEFAULTS["transfer"] and k != "registration"}
    for key in ("scales", "inner_levels"):
        if isinstance(found.get(key), (str, int, float)):
            found[key] = [float(s) for s in str(found[key]).split(",")]
    return found


def _prepare_transfer(options: Dict[str, Any], out: Path) -> Dict[str, Any]:
    """The options of a cohort's transfer with the template's lines computed once
    into ``out/template.lines.json``, and the checksums of the template and its
    landmarks (a rerun with other ones recomputes every subject)."""
    for key in ("template", "landmarks"):
        if key not in options:
            raise ValueError(f"the option {key!r} is needed for the task 'transfer'")
    template, marks = str(options["template"]), str(options["landmarks"])
    lines_path = out / "template.lines.json"
    given = job_options(**_transfer_options(options))
    lines = scan_lines(template, "template", options.get("level"), given)
    lines.save(lines_path)  # under a temporary name, then renamed
    return {**options, "template": template, "landmarks": marks, "template_lines": str(lines_path),
            "template_sha256": sha256(template), "landmarks_sha256": sha256(marks)}


def _task_transfer(path: str, options: Dict[str, Any], folder: Path) -> Tuple[Dict[str, int], List[str]]:
    found = transfer(options["template"], options["landmarks"], path, level=options.get("level"),
                     template_lines=options["template_lines"], space=options.get("space"),
                     output=folder / "landmarks.mrk.json", **_transfer_options(options))
    _crestline.write_labelled_points(str(folder / "landmarks.csv"), found["labels"], found["positions"],
                                     found["confidence"], found["flagged"], "RAS")
    return {"points": len(found["labels"]), "lines": 0}, ["landmarks.csv", "landmarks.mrk.json"]


TASK_FUNCTIONS = {
    "landmarks": _task_landmarks,
    "ridges": _task_ridges,
    "crest_lines": _task_crest_lines,
    "isosurface": _task_isosurface,
    "curvature": _task_curvature,
    "transfer": _task_transfer,
}


def _finished(folder: Path, checksum: str, task: str, options: Dict[str, Any]) -> Optional[Dict[str, Any]]:
    """The manifest of a complete earlier run with the same input and options."""
    try:
        manifest: Dict[str, Any] = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError):
        return None
    same = (manifest.get("sha256"), manifest.get("task"), manifest.get("options")) == (checksum, task, options)
    if same and all((folder / name).exists() for name in manifest.get("outputs", [])):
        return manifest
    return None


def run_subject(subject: str, path: str, task: str, options: Dict[str, Any], out_dir: str) -> Dict[str, Any]:
    """Run ``task`` on one input (on a worker), writing into ``out_dir/subject``;
    the summary row. Never raises for a bad input: its row says what went wrong."""
    folder = Path(out_dir) / subject
    row: Dict[str, Any] = {"subject": subject, "path": path, "status": "ok", "error": "", "points": 0,
                           "lines": 0, "seconds": 0.0, "reused": False, "outputs": ""}
    started = time.perf_counter()
    try:
        checksum = sha256(path)
        manifest = _finished(folder, checksum, task, options)
        if manifest is None:
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir(parents=True)
            counts, outputs = TASK_FUNCTIONS[task](path, options, folder)
            manifest = {
                "subject": subject, "input": path, "sha256": checksum, "task": task, "options": options,
                "outputs": outputs, "counts": counts, "seconds": time.perf_counter() - started,
                "finished": datetime.now(timezone.utc).isoformat(),
            }
            _write_atomically(folder / "manifest.json",
                              lambda partial: partial.write_text(json.dumps(manifest, indent=1)))
        else:
            row["reused"] = True
        row.update(manifest["counts"])
        row["seconds"] = manifest["seconds"]
        row["outputs"] = ";".join(str(folder / name) for name in manifest["outputs"])
    except Exception as error:  # one bad scan must not stop the cohort
        shutil.rmtree(folder, ignore_errors=True)
        message = str(error)
        row.update(status="error", error=message if path in message else f"{path}: {message}",
                   seconds=time.perf_counter() - started)
    return row


def machine_memory() -> Optional[int]:
    """The machine's memory in bytes, if the system tells."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def default_workers() -> int:
    """One worker per core, fewer if their tasks' peaks would not fit in memory."""
    cores = os.cpu_count() or 1
    memory = machine_memory()
    return cores if memory is None else max(1, min(cores, memory // TASK_PEAK_BYTES))


def worker_environment(workers: int) -> Dict[str, str]:
    """The environment of each of ``workers`` worker processes on this machine: the
    cores shared out among them, so that the library's threads (rayon) in several
    workers do not contend for the same cores."""
    cores = os.cpu_count() or 1
    return {"RAYON_NUM_THREADS": str(max(1, cores // workers))}


def _write_tables(rows: List[Dict[str, Any]], out: Path, task: str) -> None:
    """summary.csv (and .parquet), and for landmarks all of them in one table."""

    def write_csv(path: Path, columns: Sequence[str], records: Iterable[Sequence[Any]]) -> None:
        def write(partial: Path) -> None:
            with open(partial, "w", newline="") as f:
                table = csv.writer(f)
                table.writerow(columns)
                table.writerows(records)

        _write_atomically(path, write)

    write_csv(out / "summary.csv", SUMMARY_COLUMNS, ([row[c] for c in SUMMARY_COLUMNS] for row in rows))
    tables = {"summary": [{c: row[c] for c in SUMMARY_COLUMNS} for row in rows]}
    if task == "landmarks":
        records = []
        header: List[str] = []
        for row in rows:
            if row["status"] == "ok":
                with open(out / row["subject"] / "landmarks.csv", newline="") as f:
                    header, *table = list(csv.reader(f))
                records += [[row["subject"], *r] for r in table]
        columns = ("subject", *header)
        write_csv(out / "landmarks.csv", columns, records)
        tables["landmarks"] = [dict(zip(columns, r)) for r in records]
    if task == "transfer":
        columns = ("subject", "label", "x", "y", "z", "confidence", "flagged")
        records = []
        for row in rows:
            if row["status"] == "ok":
                with open(out / row["subject"] / "landmarks.csv", newline="") as f:
                    records += [[row["subject"], *(r[c] for c in columns[1:])] for r in csv.DictReader(f)]
        write_csv(out / "transferred.csv", columns, records)
        tables["transferred"] = [dict(zip(columns, r)) for r in records]
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return
    for name, records_of in tables.items():
        if name == "landmarks":
            records_of = [{**r, **{c: float(r[c]) for c in ("x", "y", "z", "curvature")},
                           **{c: int(r[c]) for c in ("id", "line")}} for r in records_of]
        if name == "transferred":
            records_of = [{**r, **{c: float(r[c]) for c in ("x", "y", "z", "confidence")},
                           "flagged": r["flagged"] == "true"} for r in records_of]
        _write_atomically(out / f"{name}.parquet",
                          lambda partial, t=records_of: pq.write_table(pa.Table.from_pylist(t), partial))


def _progress_bar(total: int, enabled: bool) -> Any:
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc="crestline cohort", unit="scan")


def run(
    inputs: Union[PathLike, Sequence[PathLike]],
    out_dir: PathLike,
    task: str = "landmarks",
    options: Optional[Dict[str, Any]] = None,
    client: Any = None,
    progress: bool = True,
) -> List[Dict[str, Any]]:
    """Run ``task`` on every input on a Dask cluster and return one row per input
    (in input order): subject, path, status (``ok``/``error``), error, points,
    lines, seconds, reused (a complete earlier result was kept), outputs.

    ``inputs``: paths of meshes or images, or a CSV file with a ``path`` column and
    per-subject options (which override ``options``). ``client``: a
    ``dask.distributed.Client``; with None a LocalCluster sized to the machine is
    started for the run and closed after it, the cores shared out among its workers
(``RAYON_NUM_THREADS``; give a cluster of your own ``worker_environment(n)``). ``progress``: a tqdm bar when tqdm is
    installed.
    """
    if task not in TASKS:
        raise ValueError(f"task: expected one of {TASKS}, got {task!r}")
    importing_main = getattr(multiprocessing.current_process(), "_inheriting", False)
    if client is None and (importing_main or multiprocessing.parent_process() is not None):
        raise RuntimeError(
            "crestline.cohort.run was called while a worker process imported the main script: "
            'in a script, call it under `if __name__ == "__main__":` (worker processes import the script again)'
        )
    if options is not None and not isinstance(options, dict):
        raise TypeError(f"options: expected a dict, got {type(options).__name__}")
    subjects = read_inputs(inputs)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if task == "transfer":
        options = _prepare_transfer(options or {}, out)
    from dask.distributed import Client, LocalCluster, as_completed

    own = client is None
    if own:
        workers = default_workers()
        memory = machine_memory()
        share = "auto" if memory is None else memory // workers
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, memory_limit=share,
                               dashboard_address=None, env=worker_environment(workers))
        client = Client(cluster)
    try:
        futures = {
            client.submit(run_subject, subject, path, task, {**(options or {}), **own_options}, str(out),
                          key=f"crestline-{task}-{subject}-{uuid.uuid4().hex}", pure=False): index
            for index, (subject, path, own_options) in enumerate(subjects)
        }
        rows: List[Optional[Dict[str, Any]]] = [None] * len(subjects)
        bar = _progress_bar(len(subjects), progress)
        for future in as_completed(futures):
            index = futures[future]
            subject, path, _ = subjects[index]
            try:
                rows[index] = future.result()
            except Exception as error:  # the worker died too often
                rows[index] = {"subject": subject, "path": path, "status": "error",
                               "error": f"{path}: the worker running it died ({error})", "points": 0, "lines": 0,
                               "seconds": 0.0, "reused": False, "outputs": ""}
            if bar is not None:
                bar.update()
        if bar is not None:
            bar.close()
    finally:
        if own:
            client.close()
            cluster.close()
    done = [row for row in rows if row is not None]
    _write_tables(done, out, task)
    return done


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The ``crestline-cohort`` command."""
    parser = argparse.ArgumentParser(
        prog="crestline-cohort",
        description="Run a crestline task on every scan of a cohort on a Dask cluster "
                    "(resumable: finished subjects are skipped).")
    parser.add_argument("inputs", nargs="+", help="mesh or image files, or one CSV file with a 'path' column")
    parser.add_argument("-o", "--out-dir", required=True, help="folder of the outputs, one sub-folder per subject")
    parser.add_argument("--task", choices=TASKS, default="landmarks")
    parser.add_argument("--level", type=float, help="the isosurface's value (images)")
    parser.add_argument("--sigma", type=float, help="Gaussian smoothing of images, world units")
    parser.add_argument("--template", help="the template scan (task transfer)")
    parser.add_argument("--landmarks", help="the template's landmarks file (task transfer)")
    parser.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                        help="any other option of the task, e.g. --option radius=4 (repeatable)")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local cluster)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    options: Dict[str, Any] = {}
    for item in args.option:
        key, sep, value = item.partition("=")
        if not sep or not key:
            parser.error(f"--option {item!r}: expected KEY=VALUE")
        options[key] = _option_value(value)
    for key in ("level", "sigma", "template", "landmarks"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    inputs = args.inputs[0] if len(args.inputs) == 1 and args.inputs[0].lower().endswith(".csv") else args.inputs
    client = None
    if args.scheduler:
        from dask.distributed import Client

        client = Client(args.scheduler)
    rows = run(inputs, args.out_dir, task=args.task, options=options, client=client,
               progress=not args.no_progress)
    failed = [row for row in rows if row["status"] != "ok"]
    for row in failed:
        print(f"crestline-cohort: {row['error']}", file=sys.stderr)
    print(f"crestline-cohort: {len(rows) - len(failed)} ok, {len(failed)} failed; "
          f"summary in {Path(args.out_dir) / 'summary.csv'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
