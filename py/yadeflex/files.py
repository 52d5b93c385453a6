"""Files a run can trust: replaced whole or not at all, written by one process at a time, complete
up to the last row when the run stops, and never mixed with an earlier run's files.

- write_atomic(path, text): a temporary file in the same folder, renamed over path (a rename
  within one file system is atomic: a reader sees the old file or the new one, never a part).
- locked(path): an exclusive flock on path for a `with` block; the kernel releases it when the
  process dies, so a killed run leaves no stale lock.
- CsvStream: a CSV file appended to and flushed row by row.
- ResultsFolder: a run's output folder, checked writable, held by one run, cleared of the files an
  earlier run wrote there (and only those).
"""
import contextlib
import csv
import fcntl
import json
import os
import re
import tempfile


def write_atomic(path, text, mode=0o644):
    """Write text to path through a temporary file in the same folder and a rename."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=os.path.splitext(path)[1])
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.chmod(tmp, mode)  # mkstemp makes it 0600
        os.replace(tmp, path)
    except BaseException as e:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        if isinstance(e, OSError):  # named by the file meant, not the temporary one
            raise OSError(e.errno, e.strerror, path) from None
        raise


def write_json(path, obj):
    """write_atomic of obj as indented JSON."""
    write_atomic(path, json.dumps(obj, indent=1) + "\n")


def overwrite_json(path, obj):
    """obj as JSON over the existing file at path, in place (truncated and rewritten: on a full
    disk the file's own block still holds a short text, where write_atomic needs a new one)."""
    with open(path, "r+" if os.path.exists(path) else "w") as fh:
        fh.truncate(0)
        fh.write(json.dumps(obj) + "\n")


def write_failure(path, err):
    """One line saying why path could not be written: the OS's reason, or (a writer that gives
    none, as VTK's) the disk's free space when it is nearly full."""
    reason = os.strerror(err.errno) if getattr(err, "errno", None) else None
    if not reason:
        try:
            st = os.statvfs(os.path.dirname(os.path.abspath(path)) or ".")
            free = st.f_bavail * st.f_frsize
            reason = f"the disk is full ({free // 1024} kB free)" if free < (1 << 20) else str(err)
        except OSError:
            reason = str(err)
    return f"cannot write {path}: {reason}"


@contextlib.contextmanager
def locked(path, waiting=None):
    """Hold an exclusive flock on path (created if missing) for the `with` block. If another
    process holds it, waiting() is called once (e.g. to say what the run waits for), then this
    blocks until that process releases it or ends."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            if waiting:
                waiting()
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


class CsvStream:
    """A CSV file that holds every row appended so far, on disk (flushed) after each append, so a
    run that stops anyhow leaves its rows. Columns: `first`, then the other keys in the order they
    first appear, then `last`. A row with a key not seen before rewrites the file with the wider
    header (earlier rows get `missing` in the new column); rows are kept for that (and for the
    caller: .rows). units: column -> unit, or a function of the column: the header reads
    NAME[UNIT] (yadeflex.energy_csv.read_csv splits it); rows are keyed by the bare names."""

    def __init__(self, path, first=(), last=(), missing="", units=None):
        self.path, self.first, self.last, self.missing = path, list(first), list(last), missing
        self.unit = units if callable(units) else (lambda k, u=dict(units or {}): u.get(k))
        self.columns = None
        self.rows = []
        self._fh = None

    def _header(self, keys):
        return self.first + [k for k in keys if k not in self.first and k not in self.last] + self.last

    def append(self, row):
        try:
            self._append(row)
        except OSError as e:  # (a write on an open file names no file: this one's path is added)
            raise OSError(e.errno, e.strerror, e.filename or self.path) from None

    def _append(self, row):
        self.rows.append(row)
        new = [k for k in row if self.columns is None or k not in self.columns]
        if new:
            self.columns = self._header((self.columns or []) + new)
            self.close()
            tmp = self.path + ".tmp"
            try:
                self._fh = open(tmp, "w", newline="")
                self._writer = csv.DictWriter(self._fh, fieldnames=self.columns, restval=self.missing)
                csv.writer(self._fh).writerow([k if self.unit(k) is None else f"{k}[{self.unit(k)}]" for k in self.columns])
                self._writer.writerows(self.rows)
                self._fh.flush()
                os.replace(tmp, self.path)  # the open file is now the one at path
            except BaseException:
                self.close()
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(tmp)
                raise
        else:
            self._writer.writerow(row)
            self._fh.flush()

    def close(self):
        if self._fh is not None:
            fh, self._fh = self._fh, None
            try:
                fh.close()
            except OSError as e:
                raise OSError(e.errno, e.strerror, e.filename or self.path) from None


class ResultsFolder:
    """The output folder of one run.

    Opening it: creates the folder, refuses one this process cannot write (ValueError naming the
    folder and the reason, before anything costly runs), takes an exclusive lock (a second run
    into the same folder waits for the first), and removes what an earlier run wrote there: the
    given `files` and the temporary files they are written through (write_atomic's .tmp-*,
    CsvStream's NAME.tmp), and in each `folders` entry (subfolder name -> regular expression)
    the files whose names match (the subfolder is removed if that empties it). Anything else in
    the folder is left alone. Close it (or use it in a `with` block) to release the lock."""

    LOCK = ".lock"

    def __init__(self, path, files=(), folders=None, waiting=None):
        self.path = os.path.abspath(path)
        try:
            os.makedirs(self.path, exist_ok=True)
            fd, probe = tempfile.mkstemp(dir=self.path, prefix=".tmp-probe-")
            os.close(fd)
            os.unlink(probe)
        except OSError as e:
            raise ValueError(f"the output folder {self.path} cannot be written: {e.strerror or e}") from None
        self._lock = locked(os.path.join(self.path, self.LOCK), waiting)
        self._lock.__enter__()
        try:
            clear_matching(self.path, "|".join([r"\.tmp-.*"] + [re.escape(n) + r"(\.tmp)?" for n in files]), remove_empty=False)
            for sub, pattern in (folders or {}).items():
                clear_matching(os.path.join(self.path, sub), pattern)
        except OSError as e:
            self.close()
            raise ValueError(f"the output folder {self.path} holds an earlier run's {e.filename}, which cannot be removed: "
                             f"{e.strerror or e}") from None
        except BaseException:
            self.close()
            raise

    def file(self, name):
        return os.path.join(self.path, name)

    def close(self):
        if self._lock is not None:
            self._lock.__exit__(None, None, None)
            self._lock = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def clear_matching(folder, pattern, remove_empty=True):
    """Remove the files of folder whose names match the regular expression pattern (whole name),
    and with remove_empty the folder itself if that leaves it empty. A missing folder is fine."""
    rx = re.compile(pattern)
    try:
        names = os.listdir(folder)
    except FileNotFoundError:
        return
    for n in names:
        if rx.fullmatch(n):
            with contextlib.suppress(FileNotFoundError):
                os.unlink(os.path.join(folder, n))
    if remove_empty:
        with contextlib.suppress(OSError):
            os.rmdir(folder)  # only if empty
