"""Write failures and non-finite numbers: one line naming the output, nothing left behind.

The disk filling up is simulated here at each kind of write (a libvips save, a JSON document,
the publishing rename), so the mapping is tested wherever the tests run;
``tests/python/cli/test_full_disk.py`` fills a real tmpfs where one can be mounted.
"""

from __future__ import annotations

import errno
import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset import publish as publish_mod
from lanterna.tiler.dataset.export import export
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.output import failure_reason, json_text
from lanterna.tiler.dataset.writer import DatasetWriter, read_description
from lanterna.tiler.iiif import pyramid
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.publishing import leftovers

#: What libvips 8.18 said when dzsave filled a 2 MB tmpfs (measured; the first lines).
DZSAVE_ENOSPC = ("unable to call dzsave", "vips__file_write: write error (516096 out of 733025 "
                 "blocks written)\nsystem error: No space left on device\nwbuffer_write: write "
                 "failed\nsystem error: Unknown error -1\n")
FULL = os.strerror(errno.ENOSPC)


def test_the_reason_is_the_systems_or_libvips_first_words() -> None:
    assert failure_reason(pyvips.Error(*DZSAVE_ENOSPC)) == "No space left on device"
    assert failure_reason(pyvips.Error("unable to call pngsave", "vips2png: unable to write "
                                       "to target x.png\n")) == "vips2png: unable to write to " \
                                                                "target x.png"
    assert failure_reason(OSError(errno.EROFS, os.strerror(errno.EROFS))) == \
        "Read-only file system"


def test_the_reason_survives_two_saves_failing_at_once(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """dzsave and the full/max thread fail together; libvips gave the reason to the thread."""
    def dzsave(self: pyvips.Image, *args: Any, **kwargs: Any) -> None:
        raise pyvips.Error("unable to call dzsave", "wbuffer_write: write failed")

    def render(*args: Any) -> None:
        raise pyvips.Error("unable to call pngsave", f"system error: {FULL}")

    monkeypatch.setattr(pyvips.Image, "dzsave", dzsave, raising=False)
    monkeypatch.setattr(pyramid, "_render", render)
    with pytest.raises(pyvips.Error) as err:
        pyramid.write_pyramid(vips_from_array(np.zeros((20, 30, 3), np.uint8)),
                              tmp_path / "img", "http://x/img")
    assert err.value.message == "unable to call dzsave"
    assert failure_reason(err.value) == FULL


def _source(tmp_path: Path) -> Path:
    src = tmp_path / "src.ptm"
    write_ptm(src, random_ptm_of_size(300, 200), "PTM_FORMAT_LRGB")
    return src


def _dzsave_fills_the_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    def dzsave(self: pyvips.Image, *args: Any, **kwargs: Any) -> None:
        raise pyvips.Error(*DZSAVE_ENOSPC)

    monkeypatch.setattr(pyvips.Image, "dzsave", dzsave, raising=False)


def _failing(real: Callable[..., Any], when: Callable[[str, str], bool]) -> Callable[..., Any]:
    def call(src: Any, dst: Any, *args: Any, **kwargs: Any) -> Any:
        if when(os.fspath(src), os.fspath(dst)):
            raise OSError(errno.ENOSPC, FULL, os.fspath(dst))
        return real(src, dst, *args, **kwargs)

    return call


def _json_fills_the_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(os, "replace", _failing(os.replace, lambda _, d: d.endswith(
        "/lanterna.json")))


def _publish_fills_the_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(os, "replace", _failing(os.replace, lambda s, _: ".link-" in s))


def _version_fills_the_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(publish_mod.os, "rename", _failing(os.rename, lambda _, d: ".v-" in d))


FAILURES = {"libvips save": _dzsave_fills_the_disk, "JSON document": _json_fills_the_disk,
            "publishing link": _publish_fills_the_disk, "version folder": _version_fills_the_disk}


@pytest.mark.parametrize("fail", FAILURES.values(), ids=FAILURES.keys())
def test_a_full_disk_on_a_new_dataset_is_one_line_and_leaves_nothing(
        tmp_path: Path, fail: Callable[[pytest.MonkeyPatch], None],
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    src, out = _source(tmp_path), tmp_path / "root" / "obj"
    fail(monkeypatch)
    assert main(["import", str(src), "-o", str(out)]) == 2
    assert capsys.readouterr().err == (f"lanterna: error: {out}: cannot write ({FULL}); "
                                       "nothing was changed\n")
    assert leftovers(out.parent) == []


@pytest.mark.parametrize("fail", FAILURES.values(), ids=FAILURES.keys())
def test_a_full_disk_on_a_replacement_keeps_the_previous_dataset(
        tmp_path: Path, fail: Callable[[pytest.MonkeyPatch], None],
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    src, out = _source(tmp_path), tmp_path / "root" / "obj"
    assert main(["import", str(src), "-o", str(out), "--label", "before"]) == 0
    version = os.readlink(out)
    capsys.readouterr()
    fail(monkeypatch)
    assert main(["import", str(src), "-o", str(out), "--force", "--label", "after"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"lanterna: error: {out}: cannot write")
    assert os.readlink(out) == version and read_description(out)["label"] == "before"
    assert leftovers(out.parent) == ["obj"]


def _nan_layer(ds: DatasetWriter) -> None:
    img = vips_from_array(np.zeros((20, 30, 3), np.uint8))
    layer = add_image_layer(ds, img, layer_id="pic", fmt="png")
    layer["planes"][0]["scale"][1] = math.nan  # what a broken fit could produce


def test_a_non_finite_number_is_an_error_naming_the_file_and_the_value(tmp_path: Path) -> None:
    out = tmp_path / "obj"
    with pytest.raises(LanternaInputError) as err, DatasetWriter(
            out, name="obj", label="x", width=30, height=20) as ds:
        _nan_layer(ds)
    assert str(err.value) == (f"{out}/layers/pic.json: cannot write: planes[0].scale[1] is nan "
                              "(JSON has no NaN or infinity)")
    assert leftovers(tmp_path) == []


def test_json_text_refuses_infinity_anywhere() -> None:
    doc = {"a": [1, {"b": [0.5, -math.inf]}], "c": "NaN"}
    with pytest.raises(LanternaInputError, match=r"^x.json: cannot write: a\[1\]\.b\[1\] is -inf"):
        json_text(doc, Path("x.json"))
    assert json.loads(json_text({"c": "NaN", "d": 1e308}, Path("x.json"))) == {"c": "NaN",
                                                                               "d": 1e308}


def test_json_text_puts_number_arrays_on_one_line_and_leaves_strings_alone() -> None:
    basis = list(range(0, 256, 3)) * 40  # a PCA basis is thousands of bytes
    doc = {"basis": basis, "scale": [0.5, -1e-3, 2], "names": ["P0", "P1"],
           "rows": [[1, 2], [3, 4]], "text": "[1,2] and\n[3,\n 4]", "empty": []}
    text = json_text(doc, Path("x.json"))
    assert json.loads(text) == doc
    lines = text.splitlines()
    assert sum('"basis": [' in line for line in lines) == 1
    assert len(lines) < 20  # one line per number would be > 3000
    assert '"scale": [0.5, -0.001, 2]' in text and '"names": [\n' in text


def test_an_export_refuses_nan_in_an_old_dataset(tmp_path: Path) -> None:
    out = tmp_path / "root" / "obj"
    with DatasetWriter(out, name="obj", label="x", width=30, height=20) as ds:
        add_image_layer(ds, vips_from_array(np.zeros((20, 30, 3), np.uint8)), layer_id="pic")
    doc = json.loads((out / "layers/pic.json").read_text())
    doc["planes"][0]["bias"][0] = math.inf
    (out / "layers/pic.json").write_text(json.dumps(doc))  # as json.dumps writes it: Infinity
    site = tmp_path / "site"
    with pytest.raises(LanternaInputError) as err:
        export(out, site, "https://example.org/iiif")
    assert str(err.value) == (f"{site}/obj/layers/pic.json: cannot write: planes[0].bias[0] is "
                              "inf (JSON has no NaN or infinity)")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["root"]
