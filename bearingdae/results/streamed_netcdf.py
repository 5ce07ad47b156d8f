"""A NetCDF result written block by block as the run goes, renamed onto its target at the end.

Pipeline: the last stage (results), for a streamed run (results/streamed_record.py). The file lives
under a hidden temporary name beside its target (the name :mod:`bearingdae.util.atomic` gives
its temporaries, so that one left by a killed writer is removed by the next write to the same
target); its ``time`` dimension is unlimited and every variable along it is chunked as (one
block, its whole other dimensions) and zlib-compressed, so an appended block only ever adds
chunks. The first block is written by xarray with the encoding :func:`~.netcdf.save` uses
(:func:`~.netcdf.prepared`: the same CF attributes, fill values, label char arrays); later
blocks are appended with netCDF4-python. :meth:`StreamWriter.finish` adds the variables known
only at the end (the extremes over the whole record), replaces the global attributes, fsyncs,
and ``os.replace``-s the file onto the target: a reader never sees a partial file there.

The blocks are written by one background thread while the run computes the next block:
zlib compression is most of a block's write (~0.25 ms per sample of the baseline at 4 000
samples per cage revolution, ~4x the rest of a sample's cost), and netCDF4 releases the GIL
in HDF5's calls, as IDA's calls do. One block at most is in flight: each
:meth:`StreamWriter.append` first waits for the previous block, whose failure it raises
(:attr:`StreamWriter.unwritten` then names the blocks not in the file, in order). HDF5 is
not thread-safe, so nothing else calls it while a block is in flight: :meth:`finish`,
:meth:`settle`, :meth:`close` and :meth:`append_file` wait for the block first. Ctrl-C does
not reach the writing thread; the end of the file is written with Ctrl-C held (as
:func:`~.netcdf.save` does). A write that fails with the disk full is reported as ENOSPC
whatever HDF5 said.
"""

from __future__ import annotations

import errno
import os
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import xarray as xr

from ..util.atomic import _disk_full, default_mode, remove_stale, temporary_prefix
from .netcdf import _ctrl_c_deferred, prepared, write_netcdf4


class StreamWriter:
    """One streamed NetCDF file: :meth:`append` blocks (Datasets along ``time``), then
    :meth:`finish` (or :meth:`abandon`). ``block``: the chunk length along time."""

    def __init__(self, target: str | Path, block: int, complevel: int = 4,
                 precision: str = "float64"):
        self.target = Path(target)
        self.block, self.complevel, self.precision = int(block), complevel, precision
        self.tmp: Path | None = None
        self._nc = None  # the open netCDF4.Dataset (from the second block on)
        self.samples = 0  #: samples in the file so far (blocks whose write completed)
        #: the blocks given to :meth:`append` whose write has not completed (after a failure:
        #: the failed block and those after it, in order)
        self.unwritten: list[xr.Dataset] = []
        self._pool: ThreadPoolExecutor | None = None
        self._pending = None  # (the Future of the block in flight, the block)
        self._created = False  # the first block went to the writer (which creates the file)

    # -- writing ---------------------------------------------------------------------------
    def append(self, ds: xr.Dataset) -> None:
        """Add the samples of ``ds`` (a block of a run, ``time`` first in every variable that
        has it) at the end of the file; the first block creates it. The write runs in the
        background: its failure is raised by the next call that waits for it (this method for
        the next block, :meth:`settle`, :meth:`finish`, :meth:`close`)."""
        self.unwritten.append(ds)
        self.settle()
        if self._pool is None:
            self._pool = ThreadPoolExecutor(max_workers=1,
                                            thread_name_prefix="bearingdae-writer")
        # the background thread only writes; the bookkeeping stays on this thread (settle)
        job = self._append if self._created else self._create
        self._created = True
        self._pending = (self._pool.submit(job, ds), ds)

    def _written(self, ds: xr.Dataset) -> None:
        self.samples += ds.sizes["time"]
        self.unwritten = [d for d in self.unwritten if d is not ds]

    def settle(self) -> None:
        """Wait for the block in flight; raise its failure (ENOSPC on a full disk)."""
        if self._pending is None:
            return
        future, ds = self._pending
        exc = future.exception()  # waits (Ctrl-C here leaves the block in flight, as it was)
        self._pending = None
        if exc is not None:
            with self._reported():
                raise exc
        self._written(ds)

    def _wait_quietly(self) -> None:
        try:
            self.settle()
        except Exception:  # noqa: BLE001 - the caller is discarding the file anyway
            pass

    def _create(self, ds: xr.Dataset) -> None:
        self.target.parent.mkdir(parents=True, exist_ok=True)
        remove_stale(self.target)
        fd, tmp = tempfile.mkstemp(prefix=temporary_prefix(self.target), suffix=".part",
                                   dir=self.target.parent)
        os.close(fd)
        self.tmp = Path(tmp)
        ds, encoding = prepared(ds, self.complevel, self.precision, chunk_time=self.block)
        ds.attrs = {}  # the global attributes come at the end (finish)
        write_netcdf4(ds, self.tmp, encoding=encoding, unlimited_dims=("time",))

    def _append(self, ds: xr.Dataset) -> None:
        n0, n1 = self.samples, self.samples + ds.sizes["time"]
        nc = self._handle()
        for name, var in ds.variables.items():
            if "time" not in var.dims:
                continue  # coordinates and the first sample's start azimuth: block 1's
            out = nc.variables[name]
            values = var.transpose(*out.dimensions).values
            out[n0:n1] = values.astype(out.dtype, copy=False)

    def _handle(self):
        """The file open for appending (kept open from the second block to the end: each
        open and close costs HDF5 a few ms)."""
        import netCDF4

        if self._nc is None:
            # a small chunk cache: kept open, netCDF's default (64 MiB per variable) would
            # hold the chunks written so far, growing with the record
            before = netCDF4.get_chunk_cache()
            netCDF4.set_chunk_cache(READ_CHUNK_CACHE_BYTES, 521, before[2])
            try:
                self._nc = netCDF4.Dataset(self.tmp, "a")
            finally:
                netCDF4.set_chunk_cache(*before)
            self._nc.set_auto_maskandscale(False)  # the values as they are (NaN: fill value)
        return self._nc

    def close(self) -> None:
        """Close the file if open (before another reader opens it), after the block in
        flight (whose failure it raises)."""
        try:
            self.settle()
        finally:
            if self._pool is not None:
                self._pool.shutdown(wait=True)
                self._pool = None
            if self._nc is not None:
                try:
                    self._nc.close()
                finally:
                    self._nc = None

    def append_file(self, source: str | Path) -> None:
        """Append every sample of another streamed file (a block at a time, each written
        before the next is read: HDF5 is called from one thread at a time)."""
        self.settle()
        with open_streamed(source) as src:
            n = src.sizes.get("time", 0)
            for a in range(0, n, self.block):
                part = src.isel(time=slice(a, min(n, a + self.block))).load()
                self.append(part)
                self.settle()

    def finish(self, attrs: dict, extra: xr.Dataset | None = None) -> Path:
        """Add ``extra`` (variables known at the end), set the global attributes to
        ``attrs``, and move the file onto the target atomically. Returns the target."""
        self.settle()
        with self._reported(), _ctrl_c_deferred():
            nc = self._handle()
            try:
                if extra is not None:
                    self._add_variables(nc, extra)
                for key in nc.ncattrs():  # none unless a caller wrote some
                    nc.delncattr(key)
                from .netcdf import char_attrs

                for key, value in char_attrs(attrs).items():  # as save() writes them
                    if isinstance(value, list) and all(isinstance(v, str) for v in value):
                        nc.setncattr_string(key, value)
                    else:
                        nc.setncattr(key, value)
            finally:
                self.close()
            with open(self.tmp, "rb") as fh:
                os.fsync(fh.fileno())
            os.chmod(self.tmp, default_mode())
            os.replace(self.tmp, self.target)
        self.tmp = None
        return self.target

    def _add_variables(self, nc, extra: xr.Dataset) -> None:
        """The numeric data variables of ``extra`` as :func:`~.netcdf.save` encodes them
        (zlib, ``precision``, NaN fill value, their attributes and ``coordinates``), written
        with netCDF4 into the open file (cheaper than a second xarray write)."""
        import netCDF4
        import numpy as np

        for name, var in extra.coords.items():  # a dimension of its own (frequency_name, thermal_node)
            if name in nc.variables or var.dims != (name,):
                continue
            if name not in nc.dimensions:
                nc.createDimension(name, var.size)
            if var.dtype.kind in "OUS":  # labels as char arrays, as save() writes them
                text = np.array([str(v).encode("utf-8") for v in var.values])
                width = max(1, text.dtype.itemsize)
                if f"string{width}" not in nc.dimensions:
                    nc.createDimension(f"string{width}", width)
                out = nc.createVariable(name, "S1", (name, f"string{width}"))
                out.setncatts({**var.attrs, "_Encoding": "utf-8"})  # read back as text
                out[...] = netCDF4.stringtochar(text.astype(f"S{width}"))
            else:
                out = nc.createVariable(name, var.dtype, (name,))
                out.setncatts(dict(var.attrs))
                out[...] = var.values
        for name, var in extra.data_vars.items():
            for dim in var.dims:  # a dimension no per-sample variable had (output.variables
                if dim not in nc.dimensions:  # keeping the extremes alone)
                    nc.createDimension(dim, var.sizes[dim])
            dtype = np.dtype(self.precision) if var.dtype.kind == "f" else var.dtype
            chunks = (tuple(self.block if d == "time" else max(1, var.sizes[d])
                            for d in var.dims) if "time" in var.dims else None)
            out = nc.createVariable(name, dtype, var.dims, zlib=True,
                                    complevel=self.complevel, chunksizes=chunks,
                                    fill_value=dtype.type(np.nan) if dtype.kind == "f"
                                    else None)
            attrs = dict(var.attrs)
            if "coordinates" in var.encoding:
                attrs["coordinates"] = var.encoding["coordinates"]
            out.setncatts(attrs)
            out.set_auto_maskandscale(False)
            out[...] = var.values.astype(dtype, copy=False)

    def abandon(self) -> None:
        """Remove the temporary file (nothing reaches the target)."""
        self._wait_quietly()
        try:
            self.close()
        except Exception:  # noqa: BLE001 - a file that failed to write may fail to close
            pass
        if self.tmp is not None:
            try:
                os.unlink(self.tmp)
            except OSError:
                pass
            self.tmp = None

    def _reported(self):
        return _FullDiskSaid(self.target)


class _FullDiskSaid:
    """A write failure on a full disk as OSError(ENOSPC) naming the target (netCDF4 says only
    "NetCDF: HDF error"); any other failure as it came."""

    def __init__(self, target: Path):
        self.target = target

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if exc is None or not isinstance(exc, Exception):
            return False
        if _disk_full(self.target.parent, exc):
            raise OSError(errno.ENOSPC, f"{os.strerror(errno.ENOSPC)} (the writer said: "
                          f"{type(exc).__name__}: {exc})", str(self.target)) from exc
        return False


def block_length(record_samples: int) -> int:
    """Samples per streamed block and per chunk along time: the record split into equal
    blocks of at most :data:`BLOCK_SAMPLES` (601 samples: two of 301). Each append then
    fills whole chunks, and the last chunk is nearly full: HDF5 compresses a chunk whole, so
    a last block of 89 samples in a chunk of 512 cost as much as ~180 (measured)."""
    n = max(1, int(record_samples))
    blocks = -(-n // int(BLOCK_SAMPLES))
    return -(-n // blocks)


#: Samples per streamed block. What a block holds in memory while it is projected and written
#: is ~25 kB per sample on the baseline (20 rollers x 10 slices x 2 races x 7 slice variables,
#: float64, plus their transient copies): 512 samples are ~13-30 MB, whatever the record's
#: length (two blocks while one is written in the background and the next is gathered).
#: Fewer, longer blocks cost less per sample (one Dataset, one append per block): the default
#: run (601 samples) is two blocks and costs the CPU of the in-memory path
#: (docs/performance.md, "Memory").
BLOCK_SAMPLES = 512


#: HDF5's chunk cache per variable of a streamed file opened for reading [bytes]: netCDF's
#: default keeps up to 64 MiB of decompressed chunks per variable once read (measured: the
#: overview of a 300-revolution file grew the process by 70 MB reading roller 1's slice loads);
#: a figure reads a long record a piece at a time (plots/plotting.py), each chunk once.
READ_CHUNK_CACHE_BYTES = 1 << 20


def open_streamed(path) -> xr.Dataset:
    """A result file opened lazily, each variable's chunk cache
    :data:`READ_CHUNK_CACHE_BYTES`: reading parts of a long record keeps memory bounded."""
    import netCDF4

    before = netCDF4.get_chunk_cache()
    netCDF4.set_chunk_cache(READ_CHUNK_CACHE_BYTES, 521, before[2])
    try:
        return xr.open_dataset(path, engine="netcdf4", decode_timedelta=False)
    finally:
        netCDF4.set_chunk_cache(*before)


def writable_precision(scene) -> str:
    """The floating-point type of a scene's result file (``[output] precision``)."""
    return str(getattr(scene, "output_precision", "float64"))


__all__ = ["StreamWriter", "block_length", "BLOCK_SAMPLES", "writable_precision"]
