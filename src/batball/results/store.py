"""The results store: one folder per run, keyed by the hash of its inputs, written atomically.

A run of test ``ccor`` with inputs ``I`` lives in ``<root>/ccor-<inputs_hash(I)>/`` and holds
``summary.json`` (written last, with ``"complete": true``), ``history.csv``, fields and figures.
Every file is written to a temporary name in the same folder and moved onto its final name with
``os.replace``, so a reader sees either the old file or the new one, never half a file; an
interrupted run leaves no ``summary.json`` and is simply run again.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import re
import secrets
import time
import zipfile
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from batball.errors import SpecError

#: File name of a run's summary; its presence with ``"complete": true`` marks a finished run.
SUMMARY_NAME = "summary.json"

_HASH_LENGTH = 12
_TEST_NAME = re.compile(r"^[a-z0-9][a-z0-9_.-]*$")


def _to_json(value: Any) -> Any:
    """JSON encoding of what ``json`` does not know: NumPy scalars and arrays, paths."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Path):
        return value.as_posix()
    raise TypeError(f"not JSON-serialisable: {type(value).__name__}")


def canonical_json(inputs: Mapping[str, Any]) -> str:
    """``inputs`` as canonical JSON: sorted keys, no spaces, shortest float repr, no NaN."""
    return json.dumps(
        inputs, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False,
        default=_to_json,
    )  # fmt: skip


def inputs_hash(inputs: Mapping[str, Any]) -> str:
    """First 12 hex digits of the SHA-256 of the canonical JSON of ``inputs``.

    Args:
        inputs: JSON-able mapping (strings, numbers, bools, None, lists, dicts, NumPy values);
            key order does not matter, any value change does.
    """
    digest = hashlib.sha256(canonical_json(inputs).encode("utf-8")).hexdigest()
    return digest[:_HASH_LENGTH]


def run_folder(root: Path, test: str, inputs: Mapping[str, Any]) -> Path:
    """``root/<test>-<inputs_hash(inputs)>`` (not created here; the writers create folders).

    Raises:
        ValueError: ``test`` is not a lower-case name such as ``"ccor"`` or ``"barrel"``.
    """
    if not _TEST_NAME.match(test):
        raise ValueError(f"test name {test!r} must match {_TEST_NAME.pattern}")
    return Path(root) / f"{test}-{inputs_hash(inputs)}"


def _existing_ancestor(path: Path) -> Path:
    """``path`` itself if it exists, else its nearest existing ancestor folder (or file)."""
    path = Path(os.path.abspath(path))
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def check_output_folder(field: str, path: str | Path) -> Path:
    """``path`` as a folder results can be written to (made on first write), checked before a
    run starts: not a file, under a folder that exists or can be made, and writable. A
    :class:`SpecError` naming ``field`` otherwise."""
    path = Path(path)
    found = _existing_ancestor(path)
    if not found.is_dir():
        itself = found == Path(os.path.abspath(path))
        what = "a file of that name exists" if itself else f"{found} is a file"
        raise SpecError(field, str(path), f"a folder ({what})")
    if not os.access(found, os.W_OK | os.X_OK):
        raise SpecError(field, str(path), f"a folder this user can write ({found} is not)")
    return path


def check_output_file(field: str, path: str | Path) -> Path:
    """``path`` as a file that can be written (its folders made on write), checked before a run
    starts: not a folder, its folder writable. A :class:`SpecError` naming ``field`` otherwise."""
    path = Path(path)
    if path.is_dir():
        raise SpecError(field, str(path), "a file name (a folder of that name exists)")
    check_output_folder(field, path.parent)
    return path


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success move it onto ``path``, else remove it.

    The temporary name keeps the suffix (``.png``, ``.vtu``), so writers that infer the format
    from it (matplotlib ``savefig``, meshio) work unchanged. Parent folders are created.

    Example:
        >>> with atomic_path(folder / "force.png") as tmp:   # doctest: +SKIP
        ...     figure.savefig(tmp)
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.{secrets.token_hex(6)}.tmp{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_text_atomic(path: Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically, flushed to disk before the rename."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as stream:
        stream.write(text)
        stream.flush()
        os.fsync(stream.fileno())


def write_json_atomic(path: Path, obj: Any) -> None:
    """Write ``obj`` as indented JSON to ``path`` atomically.

    Raises:
        ValueError: ``obj`` holds NaN or infinity (invalid JSON; give None instead).
        TypeError: ``obj`` holds something JSON cannot represent.
    """
    text = json.dumps(obj, indent=2, ensure_ascii=False, allow_nan=False, default=_to_json)
    write_text_atomic(path, text + "\n")


def write_csv_atomic(
    path: Path, columns: Mapping[str, np.ndarray], *, float_format: str = "%.12g"
) -> None:
    """Write equal-length 1-D columns as CSV, one header line of column names.

    Args:
        path: target file.
        columns: ``{name: values}``, each of shape ``(n_rows,)``; names carry their unit
            (``"time_ms"``, ``"force_lbf"``) and contain no comma, quote or newline.
        float_format: printf format of each value.

    Raises:
        ValueError: no columns, a column that is not 1-D, unequal lengths, or a bad name.
    """
    names = list(columns)
    if not names:
        raise ValueError("no columns to write")
    for name in names:
        if not name or any(c in name for c in ',"\n\r'):
            raise ValueError(f'column name {name!r} must be non-empty, without , " or newline')
    arrays = [np.asarray(columns[name]) for name in names]
    if any(a.ndim != 1 for a in arrays) or len({a.shape[0] for a in arrays}) != 1:
        shapes = {name: a.shape for name, a in zip(names, arrays, strict=True)}
        raise ValueError(f"columns must be 1-D of equal length; got shapes {shapes}")
    buffer = io.StringIO()
    np.savetxt(buffer, np.column_stack(arrays), fmt=float_format, delimiter=",",
               header=",".join(names), comments="")  # fmt: skip
    write_text_atomic(path, buffer.getvalue())


def arrays_digest(*arrays: np.ndarray) -> str:
    """SHA-256 (hex) of the arrays' dtypes, shapes and bytes, in order: a store key for inputs
    that are arrays (a mesh, its masses) rather than a few numbers."""
    digest = hashlib.sha256()
    for array in arrays:
        a = np.ascontiguousarray(array)
        digest.update(f"{a.dtype.str}{a.shape}".encode())
        digest.update(a.tobytes())
    return digest.hexdigest()


def write_arrays_atomic(path: Path, arrays: Mapping[str, np.ndarray]) -> None:
    """Write named arrays as an uncompressed ``.npz`` at ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as stream:
        np.savez(stream, **{name: np.asarray(a) for name, a in arrays.items()})  # type: ignore[arg-type]
        stream.flush()
        os.fsync(stream.fileno())


def load_stored_arrays(folder: Path, name: str) -> dict[str, np.ndarray] | None:
    """The arrays of ``folder/name`` (an ``.npz``) if the folder's run is complete (its summary
    is written last) and the file reads; else None, and the run is done again."""
    if load_cached_summary(folder) is None:
        return None
    try:
        with np.load(Path(folder) / name) as data:
            return {key: data[key] for key in data.files}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
        return None


def folder_files(folder: Path) -> dict[str, int]:
    """Every file of a run folder but its summary (and temporaries), by path relative to it, with
    its size in bytes."""
    folder = Path(folder)
    return {
        p.relative_to(folder).as_posix(): p.stat().st_size
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.name != SUMMARY_NAME and not p.name.startswith(".")
    }


def write_summary(folder: Path, summary: Mapping[str, Any]) -> Path:
    """Write ``folder/summary.json`` with the store's manifest added: ``"complete": true``, the
    summary's keys and the folder's files with their sizes (what a reuse checks); call it last.

    Returns:
        The path written.
    """
    path = Path(folder) / SUMMARY_NAME
    manifest = {"complete": True, "keys": sorted(summary), "files": folder_files(folder)}
    write_json_atomic(path, {**summary, **manifest})
    return path


def load_cached_summary(folder: Path) -> dict[str, Any] | None:
    """The run's summary if ``folder/summary.json`` exists, is a JSON object, is complete, holds
    every key it was written with, and every file the run wrote is there with its size.

    Returns:
        The summary dict as the run made it (without the store's manifest, so a reused run
        reports what a fresh one does), or None when the run must be (re)done: no file,
        unreadable or invalid JSON, no ``"complete": true``, a key or a file missing or changed.
        (A summary written before the manifest had keys and files is checked for completeness
        only.)
    """
    path = Path(folder) / SUMMARY_NAME
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(summary, dict) or summary.pop("complete", None) is not True:
        return None
    keys, files = summary.pop("keys", None), summary.pop("files", None)
    if keys is not None and (not isinstance(keys, list) or not set(keys) <= set(summary)):
        return None
    if files is not None:
        if not isinstance(files, dict):
            return None
        for name, size in files.items():
            file = Path(folder) / name
            if not file.is_file() or file.stat().st_size != size:
                return None
    return summary


@contextlib.contextmanager
def run_lock(folder: Path) -> Iterator[None]:
    """Hold the run key's lock (``.NAME.lock`` beside the run folder) while the block runs: a
    second process, or thread, asking for the same run waits, then finds it stored. Without
    ``fcntl`` (not POSIX) no lock is taken."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - every platform batball is tested on has it
        yield
        return
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    with open(folder.parent / f".{folder.name}.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def run_or_reuse(
    folder: Path,
    reuse: bool,
    compute: Callable[[], Any],
    summarise: Callable[[Any, float], dict[str, Any]],
    write: Callable[[Any, dict[str, Any]], None],
) -> tuple[dict[str, Any], Path]:
    """The run-folder protocol of every lab test: the complete summary of ``folder`` if ``reuse``
    and there is one; else ``compute()``, ``summarise(result, wall_seconds)`` (``run_folder``
    added) and ``write(result, summary)``, which writes the folder's files, summary.json last.
    The run key is locked throughout (:func:`run_lock`), so two identical runs compute once.

    Returns:
        (summary, folder).
    """
    with run_lock(folder):
        cached = load_cached_summary(folder) if reuse else None
        if cached is not None:
            return cached, folder
        start = time.perf_counter()
        result = compute()
        summary = summarise(result, time.perf_counter() - start)
        summary["run_folder"] = Path(folder).as_posix()
        write(result, summary)
        return summary, folder
