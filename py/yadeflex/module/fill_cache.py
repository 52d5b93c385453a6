"""The filled modules' cache: one compressed YADE save per fill key, checked against its
manifest, written atomically under a file lock; filled_module loads it or fills and saves it."""
import hashlib
import json
import os
import sys
import tempfile

from yade import O

from .fill import build_filled
from .ids import ModuleIds


CACHE_FORMAT = "yadeflex filled module"


def cache_files(params, cache_dir):
    """(scene file, its metadata file, lock file) of params' filled module in cache_dir."""
    stem = os.path.join(cache_dir, f"module-{params.fill_key()}")
    return stem + ".yade.gz", stem + ".json", stem + ".lock"


def save_compressed(path):
    """O.save into path, a '.yade.gz', without YADE's gzip writer: that writer loops for ever in its
    close when the disk fills (and returns normally having written nothing or a part when the
    folder is gone). The scene goes to an uncompressed file next to path (whose writer raises on a
    failed write), which Python's gzip then compresses into path (OSError on a full disk); the
    uncompressed file is removed whatever happens, path when it could not be written whole.
    Raises OSError naming the file."""
    import gzip
    import shutil
    raw = path[:-len(".gz")] + ".raw.yade" if path.endswith(".gz") else path + ".raw.yade"
    try:
        try:
            O.save(raw)
        except RuntimeError as e:  # ("output stream error": the disk is full)
            raise OSError(f"saving {raw} failed: {e} (disk full, or the folder gone?)") from None
        check_written(raw)
        try:
            with open(raw, "rb") as src, gzip.open(path, "wb", compresslevel=6) as dst:
                shutil.copyfileobj(src, dst, 1 << 20)
        except OSError as e:
            if os.path.exists(path):
                os.unlink(path)
            raise OSError(f"saving {path} failed: {e.strerror or e} (disk full, or the folder gone?)") from None
    finally:
        if os.path.exists(raw):
            os.unlink(raw)
    check_saved(path)


def check_written(path):
    """Raises OSError naming path unless it exists and is not empty."""
    if not os.path.exists(path) or os.path.getsize(path) == 0:
        raise OSError(f"saving {path} failed: nothing was written (disk full, or the folder gone?)")


def check_saved(path):
    """Raises OSError naming path unless it holds a whole gzip stream, as O.save writes a
    '.yade.gz' (YADE's O.save returns normally having written nothing or a part when the disk is
    full or the folder is gone)."""
    import gzip
    import zlib
    try:
        if os.path.getsize(path) == 0:
            raise OSError("nothing was written")
        with gzip.open(path, "rb") as fh:
            while fh.read(1 << 20):
                pass
    except (OSError, EOFError, zlib.error) as e:
        raise OSError(f"saving {path} failed: {e} (disk full, or the folder gone?)") from None


def _sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def cache_problem(params, cache_dir):
    """Why the cached module of params in cache_dir cannot be loaded, checked before YADE reads
    the file (a damaged or foreign archive can crash YADE's reader or make it allocate without
    bound): None if it can, "missing" if there is none, else a sentence. The metadata file
    written with the scene names the format and the key and holds the scene's size and SHA-256:
    a file of another module under this key, another YADE scene, a partial or damaged file, or
    one saved by a yade-flex without metadata are all refused."""
    f, meta_file, _ = cache_files(params, cache_dir)
    if not os.path.exists(f):
        return "missing"
    try:
        with open(meta_file) as fh:
            meta = json.load(fh)
    except FileNotFoundError:
        return f"has no metadata file {os.path.basename(meta_file)} (saved by an older yade-flex, or its save was cut short)"
    except (OSError, ValueError) as e:
        return f"has an unreadable metadata file {os.path.basename(meta_file)} ({e})"
    if not isinstance(meta, dict) or meta.get("format") != CACHE_FORMAT:
        return f"has a metadata file {os.path.basename(meta_file)} that does not describe a filled module"
    if meta.get("key") != params.fill_key():
        return f"is described as the filled module {meta.get('key')!r}, not {params.fill_key()!r}"
    if meta.get("bytes") != os.path.getsize(f) or meta.get("sha256") != _sha256(f):
        return "is not the file its metadata describes (other size or checksum: damaged, cut short, or replaced)"
    return None


def _remove_stale_temps(f, keep):
    """The temporary files of cache file f that a run killed while saving left (only a run holding
    f's lock saves f, and the caller holds it: every other one is stale); keep: the caller's own."""
    import glob
    folder, base = os.path.split(f)
    for t in glob.glob(os.path.join(glob.escape(folder), f".{glob.escape(base)}.*")):
        if os.path.abspath(t) != os.path.abspath(keep):
            try:
                os.unlink(t)
            except OSError:
                pass


def filled_module(params, cache_dir=None, progress=None):
    """The settled module on O: loaded from the cache when it holds this key (with
    params.engines(params.damping) set), else built and saved there. A cache file that
    cache_problem() refuses, or that this build cannot read (classes changed since it was
    saved), is filled again, with a message. progress(stage, steps, kinetic energy [J], its
    target [J]) is called while filling (steps 0: a stage starts). Returns (ids, cache_file,
    from_cache).

    Runs sharing a cache folder: the module is looked up and filled under a lock on its own
    lock file, so a second run asking for a module another run is filling waits for it and
    loads it; the scene and its metadata are each written to a temporary file and renamed into
    place, so a run stopped while saving leaves the old cache or none, never a part. A cache
    folder that cannot be written is refused before the fill."""
    params.validate()
    cache_dir = cache_dir or os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules")
    f, meta_file, lock = cache_files(params, cache_dir)
    key = params.fill_key()
    from ..files import locked, write_json
    try:
        os.makedirs(cache_dir, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=cache_dir, prefix=f".{os.path.basename(f)}.", suffix=".yade.gz")  # where a fill is saved
        os.close(fd)
    except OSError as e:
        raise ValueError(f"the module cache folder {cache_dir} cannot be written: {e.strerror or e}") from None
    try:
        with locked(lock, waiting=lambda: print(f"yadeflex: waiting for another run that fills the module {f}", flush=True)):
            _remove_stale_temps(f, keep=tmp)
            problem = cache_problem(params, cache_dir)
            if problem is None:
                try:
                    O.load(f)
                    stored = O.tags["yadeflex_module_key"] if "yadeflex_module_key" in O.tags.keys() else None
                except Exception as e:  # saved by a build whose classes have other attributes
                    stored, problem = None, f"cannot be read by this build ({type(e).__name__}: {e})"
                else:
                    if stored == key:
                        # (outside the try: an error here is not the cache file's, and filling again would not mend it)
                        O.engines = params.engines(params.damping)
                        return ModuleIds.from_json(O.tags["yadeflex_module"]), f, True
                    problem = f"holds the module {stored!r}, not {key!r}"
                O.reset()
            if problem != "missing":
                print(f"yadeflex: the cached module {f} {problem}; filling it again", file=sys.stderr, flush=True)
            build_filled(params, progress=progress)
            O.tags["yadeflex_module_key"] = key
            # without engines: an engine's attributes change more often than the bodies', and a
            # cache must stay readable (the impact sets its own engines anyway)
            engines_ = O.engines
            O.engines = []
            try:
                save_compressed(tmp)
            finally:
                O.engines = engines_
            meta = dict(format=CACHE_FORMAT, key=key, bytes=os.path.getsize(tmp), sha256=_sha256(tmp))
            os.chmod(tmp, 0o644)  # mkstemp makes it 0600
            os.replace(tmp, f)
            write_json(meta_file, meta)
            # go on from the file, as every later run will: the same state to the last bit, and
            # the bodies and interactions in order in memory
            O.load(f)
            O.engines = params.engines(params.damping)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return ModuleIds.from_json(O.tags["yadeflex_module"]), f, False
