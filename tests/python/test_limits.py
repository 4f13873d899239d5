"""One pixel limit for every image reader, checked from headers before anything is decoded, and
regular files only (tiler/limits.py, tiler/fileio.py; docs/reliability.md)."""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.tiler import limits
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.inputs.images import load_rgb_image
from lanterna.tiler.inputs.maps import load_band
from tests.python.fixtures.fuzz import bounded
from tests.python.fixtures.ptm import random_ptm
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.sources import png, random_image


def _jpeg_ptm_claiming(tmp_path: Path, width: int, height: int) -> Path:
    """A valid 9 × 5 JPEG-LRGB PTM whose header is rewritten to claim ``width`` × ``height``."""
    path = tmp_path / "small.ptm"
    write_ptm(path, random_ptm("lrgb", 9, 5), "PTM_FORMAT_JPEG_LRGB")
    lines = path.read_bytes().split(b"\n", 4)
    lines[2], lines[3] = str(width).encode(), str(height).encode()
    path.write_bytes(b"\n".join(lines))
    return path


def test_a_jpeg_ptm_claiming_65500_squared_is_refused_without_allocating(tmp_path: Path) -> None:
    """It used to allocate 36 GiB before looking at its first JPEG stream."""
    path = _jpeg_ptm_claiming(tmp_path, 65500, 65500)
    with bounded(seconds=5, headroom=256 << 20), pytest.raises(LanternaInputError,
                                                                match="images over"):
        read_ptm(path)
    limits.set_max_pixels(65500 * 65500)  # past the pixel limit: the streams' own headers
    try:
        with bounded(seconds=5, headroom=256 << 20), pytest.raises(
                LanternaInputError, match="JPEG stream 0 is 9x5 .* single-band 65500x65500"):
            read_ptm(path)
    finally:
        limits.set_max_pixels(None)


def test_the_limit_applies_to_every_image_reader_and_can_be_set(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch,
                                                                 capsys: pytest.CaptureFixture[str]
                                                                 ) -> None:
    image = png(tmp_path / "band.png", random_image(1, 1))  # 96 × 64 = 6,144 px
    assert load_band(image).shape == (64, 96)
    limits.set_max_pixels(6000)
    try:
        for read in (load_band, load_rgb_image):
            with pytest.raises(LanternaInputError, match=r"band.png: image is 96x64 \(0.0 Mpx\); "
                               r"images over 0.0 Mpx are refused \(--max-pixels"):
                read(image)
    finally:
        limits.set_max_pixels(None)
    monkeypatch.setenv(limits.ENVIRONMENT, "6000")
    assert limits.max_pixels() == 6000
    monkeypatch.setenv(limits.ENVIRONMENT, "lots")
    with pytest.raises(LanternaInputError, match="LANTERNA_MAX_PIXELS must be a positive integer"):
        limits.max_pixels()
    monkeypatch.delenv(limits.ENVIRONMENT)
    out = tmp_path / "ds"
    assert main(["import", str(image), "-o", str(out), "--max-pixels", "6000"]) == 2
    assert "images over" in capsys.readouterr().err and not out.exists()
    assert main(["import", str(image), "-o", str(out), "--max-pixels", "7000"]) == 0
    assert limits.max_pixels() == limits.DEFAULT_MAX_PIXELS  # the CLI put it back


def test_devices_and_fifos_are_refused_at_once(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """A description naming ``/dev/zero`` used to read without end; a FIFO used to block."""
    fifo = tmp_path / "vis.png"
    os.mkfifo(fifo)
    for source in ("/dev/zero", "vis.png"):
        desc = tmp_path / "object.json"
        desc.write_text(json.dumps({"layers": [{"id": "vis", "source": source}]}))
        status: list[int] = []
        args = ["import", str(desc), "-o", str(tmp_path / "out")]
        worker = threading.Thread(target=lambda a=args, s=status: s.append(main(a)), daemon=True)
        worker.start()
        worker.join(20)
        assert not worker.is_alive(), f"importing {source} blocked"
        err = capsys.readouterr().err
        assert status == [2] and "not a regular file" in err, err
    for reader in (load_rgb_image, load_band):
        with pytest.raises(LanternaInputError, match="not a regular file"):
            reader(Path("/dev/zero"))
    assert np.isfinite(limits.DEFAULT_MAX_PIXELS)
