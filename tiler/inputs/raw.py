"""Camera RAW input: decode through rawpy (LibRaw) into a 16-bit TIFF the stack reader streams.

rawpy is optional (``pip install 'lanterna[raw]'``) and imported only when a RAW file is
decoded.  LibRaw needs the whole raw frame in memory, so RAW files cannot be read in row bands
directly; :func:`raw_to_tiff` decodes each one once, with settings fixed for photometric work,
into a strip TIFF in a scratch folder, and the banded reader then reads that TIFF like any
other 16-bit image.

Example
-------
>>> from pathlib import Path
>>> tiff = raw_to_tiff(Path("light_01.nef"), Path("/tmp/scratch"), linear=True)  # doctest: +SKIP
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import check_regular_file
from lanterna.tiler.limits import check_pixels

#: File name suffixes (lower case) taken as camera RAW: LibRaw's common formats.
RAW_SUFFIXES = frozenset({
    ".3fr", ".ari", ".arw", ".bay", ".cr2", ".cr3", ".crw", ".dcr", ".dng", ".erf", ".fff",
    ".iiq", ".k25", ".kdc", ".mef", ".mos", ".mrw", ".nef", ".nrw", ".orf", ".ori", ".pef",
    ".raf", ".raw", ".rw2", ".rwl", ".sr2", ".srf", ".srw", ".x3f",
})

_INSTALL_HINT = "camera RAW needs rawpy: pip install rawpy (or 'lanterna[raw]')"

#: rawpy ``gamma`` pairs, ``(power, toe slope)`` as in dcraw's ``-g``: identity, and the sRGB
#: transfer curve (exponent 2.4 with a linear toe of slope 12.92; LibRaw derives the 0.055
#: offset and the breakpoint so the two pieces join).
_LINEAR_GAMMA = (1.0, 1.0)
_SRGB_GAMMA = (2.4, 12.92)


def is_raw(path: str | os.PathLike[str]) -> bool:
    """Return whether ``path`` names a camera RAW file, by its suffix (any case)."""
    return Path(path).suffix.lower() in RAW_SUFFIXES


def postprocess_params(*, linear: bool) -> dict[str, Any]:
    """Return the keyword arguments :func:`raw_to_tiff` passes to ``RawPy.postprocess``.

    Every image of a collection must be decoded with the same fixed mapping from sensor
    counts to output values, so the fit sees only the change of light:

    ``use_camera_wb=True, use_auto_wb=False``
        White balance from the camera's as-shot multipliers (DNG ``AsShotNeutral``), which are
        constant for a collection shot with a fixed white balance; never estimated from the
        picture, which would change with each light position.  Files without them fall back
        to LibRaw's daylight balance, also fixed.
    ``no_auto_bright=True, bright=1.0, exp_shift=None``
        No histogram-driven brightening (by default LibRaw rescales so 1 % of the pixels clip,
        a different gain for every image).
    ``adjust_maximum_thr=0.0``
        The white level is the file's (``WhiteLevel``), never lowered to the brightest value
        found in this image (LibRaw's default 0.75 does that for near-saturated images).
        With the file's black level subtracted, ``white − black`` maps to 65535 in the
        channel with the smallest white-balance multiplier; highlights clip
        (``highlight_mode=Clip``), so saturated pixels come out at 65535 in all channels.
    ``output_bps=16``
        16-bit output: no 8-bit quantisation of linear data.
    ``gamma=(1, 1)`` when ``linear`` else ``(2.4, 12.92)``
        Linear light (values proportional to sensor counts), or the sRGB transfer curve, to
        match what JPEG collections hold.
    ``output_color=ColorSpace.sRGB``
        The camera's colour matrix (DNG ``ColorMatrix``/LibRaw's table) converts to sRGB
        primaries, D65 white.
    ``demosaic_algorithm=AHD, half_size=False, four_color_rgb=False, median_filter_passes=0,
    noise_thr=None, fbdd_noise_reduction=Off``
        Full-resolution demosaicing with LibRaw's standard AHD, no denoising or median
        smoothing that would vary with image content.
    ``user_flip=0``
        The output pixel grid is the sensor grid: the EXIF/DNG orientation flag is ignored.
        A camera pointing straight down at an RTI subject has no reliable "up", and its
        orientation sensor may flip between frames; honouring the flag would rotate some
        images of a collection against the others and break their co-registration.
    """
    import rawpy  # lazily: the caller has already checked it is installed

    return {
        "use_camera_wb": True,
        "use_auto_wb": False,
        "no_auto_bright": True,
        "bright": 1.0,
        "adjust_maximum_thr": 0.0,
        "highlight_mode": rawpy.HighlightMode.Clip,
        "output_bps": 16,
        "gamma": _LINEAR_GAMMA if linear else _SRGB_GAMMA,
        "output_color": rawpy.ColorSpace.sRGB,
        "demosaic_algorithm": rawpy.DemosaicAlgorithm.AHD,
        "half_size": False,
        "four_color_rgb": False,
        "median_filter_passes": 0,
        "fbdd_noise_reduction": rawpy.FBDDNoiseReductionMode.Off,
        "user_flip": 0,
    }


def _libraw_message(err: Exception) -> str:
    """Return LibRaw's message (rawpy passes it as bytes) as one line of text."""
    arg = err.args[0] if err.args else ""
    text = arg.decode(errors="replace") if isinstance(arg, bytes) else str(arg)
    return text.strip().splitlines()[0] if text.strip() else type(err).__name__


def decode_raw(path: Path, *, linear: bool) -> npt.NDArray[np.uint16]:
    """Decode the RAW file ``path`` to ``(H, W, 3)`` uint16 sRGB with :func:`postprocess_params`.

    Raises
    ------
    LanternaInputError
        If rawpy is not installed, or naming ``path`` if LibRaw cannot read or decode it.
    """
    try:
        import rawpy
    except ImportError:
        raise LanternaInputError(path, _INSTALL_HINT) from None
    check_regular_file(path, "a camera RAW file")
    try:
        with rawpy.imread(str(path)) as raw:
            check_pixels(path, int(raw.sizes.width), int(raw.sizes.height), "the camera RAW image")
            rgb = raw.postprocess(**postprocess_params(linear=linear))
    except rawpy.LibRawError as err:
        raise LanternaInputError(path, f"cannot decode camera RAW ({_libraw_message(err)})") \
            from None
    except (OSError, MemoryError) as err:
        raise LanternaInputError(path, f"cannot decode camera RAW ({err})") from None
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.dtype != np.uint16:
        raise LanternaInputError(path, f"camera RAW decoded to an unexpected "
                                 f"{rgb.dtype} array of shape {rgb.shape}")
    return np.ascontiguousarray(rgb, np.uint16)


def scratch_name(path: Path, *, linear: bool) -> str:
    """Return the TIFF name for ``path`` in a scratch folder: its stem plus a short hash.

    The hash covers the absolute source path and the curve, so files with one stem in
    different folders, or one file decoded both ways, never share a scratch file.
    """
    key = f"{path.resolve()}\0{'linear' if linear else 'srgb'}".encode()
    return f"{path.stem}.{hashlib.sha1(key).hexdigest()[:10]}.tif"


def raw_to_tiff(path: Path, scratch_dir: Path, *, linear: bool) -> Path:
    """Decode the camera RAW ``path`` into a 16-bit RGB TIFF in ``scratch_dir``; return it.

    The decode uses :func:`postprocess_params` (camera white balance, the file's black and
    white levels, no auto-brightening, sRGB primaries, linear or sRGB curve, no rotation).
    The TIFF is an uncompressed strip (not tiled) RGB 16-bit file, ``6 · W · H`` bytes, so a
    sequential reader decodes it top to bottom in row bands at disk speed (for a 24 MP frame
    deflate saved little on noisy sensor data and cost about 2 s to write and 1 s per read
    pass, against 0.1 s uncompressed; the reader may make several passes).  It is
    written under a temporary name and renamed into place, so a reader never sees half a file;
    an existing file of the same name is replaced.  The caller owns ``scratch_dir`` and deletes
    it when done.  Decoding holds the full frame in memory (about ``6 · W · H`` bytes, plus
    LibRaw's own buffers), one file at a time.

    Parameters
    ----------
    path
        A RAW file (see :data:`RAW_SUFFIXES`).
    scratch_dir
        Existing or new folder for the decoded TIFFs.
    linear
        ``True`` for linear light (``gamma=(1, 1)``), ``False`` for the sRGB curve.

    Raises
    ------
    LanternaInputError
        If rawpy is missing, or naming ``path`` if it cannot be decoded.
    """
    rgb = decode_raw(path, linear=linear)
    height, width = rgb.shape[:2]
    image = pyvips.Image.new_from_memory(rgb.data, width, height, 3, "ushort")
    image = image.copy(interpretation="rgb16")
    scratch_dir.mkdir(parents=True, exist_ok=True)
    target = scratch_dir / scratch_name(path, linear=linear)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=".tmp", dir=scratch_dir)
    os.close(fd)
    try:
        image.tiffsave(tmp_name, compression="none", tile=False,
                       bigtiff=rgb.nbytes > 3_500_000_000)
        os.replace(tmp_name, target)
    except (pyvips.Error, OSError) as err:
        Path(tmp_name).unlink(missing_ok=True)
        first = str(err).strip().splitlines()[0] if str(err).strip() else "write error"
        raise LanternaInputError(path, f"cannot write the decoded TIFF to {scratch_dir} "
                                 f"({first})") from None
    return target
