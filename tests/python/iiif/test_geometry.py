"""Pure pyramid geometry, table-driven."""

from __future__ import annotations

import pytest

from lanterna.tiler.iiif import geometry as geo


@pytest.mark.parametrize(
    ("w", "h", "ts", "factors"),
    [
        (200, 150, 256, [1]),
        (256, 256, 256, [1]),
        (257, 10, 256, [1, 2]),
        (1000, 1000, 256, [1, 2, 4]),
        (1001, 777, 256, [1, 2, 4]),
        (300, 1000, 256, [1, 2, 4]),
        (12345, 6789, 512, [1, 2, 4, 8, 16, 32]),
    ],
)
def test_scale_factors_stop_at_one_tile(w: int, h: int, ts: int, factors: list[int]) -> None:
    assert geo.scale_factors(w, h, ts) == factors
    lw, lh = geo.level_size(w, h, factors[-1])
    assert lw <= ts and lh <= ts


def test_scale_factors_reject_empty_image() -> None:
    with pytest.raises(ValueError):
        geo.scale_factors(0, 10, 256)


def test_spec_tiles_cover_each_level_exactly() -> None:
    w, h, ts = 1001, 777, 256
    for f in geo.scale_factors(w, h, ts):
        tiles = list(geo.spec_tiles(w, h, ts, f))
        assert sum(t.w * t.h for t in tiles) == w * h
        lw, lh = geo.level_size(w, h, f)
        assert max(t.x + t.w for t in tiles) == w and max(t.y + t.h for t in tiles) == h
        assert sum(t.sw for t in tiles if t.y == 0) == lw
        assert sum(t.sh for t in tiles if t.x == 0) == lh


@pytest.mark.parametrize(
    ("req", "path"),
    [
        (geo.TileRequest(0, 0, 300, 200, 300, 200), "full/max"),
        (geo.TileRequest(0, 0, 300, 200, 150, 100), "full/150,100"),
        (geo.TileRequest(256, 0, 44, 200, 44, 200), "256,0,44,200/44,200"),
    ],
)
def test_canonical_path(req: geo.TileRequest, path: str) -> None:
    assert geo.canonical_path(300, 200, req) == path
    assert geo.parse_region_size(300, 200, path) == req


def test_osd_paths_single_tile_image_asks_for_full_max() -> None:
    assert list(geo.osd_tile_paths(200, 150, 256, [1])) == ["full/max"]


def test_osd_paths_match_spec_paths_for_multi_tile_levels() -> None:
    w, h, ts = 1001, 777, 256
    factors = geo.scale_factors(w, h, ts)
    osd = set(geo.osd_tile_paths(w, h, ts, factors))
    spec = {geo.canonical_path(w, h, t) for f in factors for t in geo.spec_tiles(w, h, ts, f)}
    assert osd == spec
    assert "1024,768,512,9/0,0" not in osd  # no empty tiles
    assert "768,768,233,9/233,9" in osd
