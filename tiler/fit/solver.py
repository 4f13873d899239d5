"""The models of one set of lights, ready to solve bands: their pseudo-inverses (PTM, HSH) or
checks (the photometric models), and the float outputs of each band
(:meth:`Solver.solve`). :func:`~lanterna.tiler.fit.engine.fit_stream` makes one for every light
and one for the leave-one-out report's training lights.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import cast

import numpy as np
import numpy.typing as npt

from lanterna.tiler.render.shading import srgb_to_linear

from . import bands as fb
from .hsh import hsh_design_matrix, hsh_pinv
from .normals import check_lights
from .ptm import ptm_design_matrix, ptm_pinv

Lights = npt.NDArray[np.float64]


@dataclass
class Solver:
    """The pseudo-inverses (or checks) of the requested models for one set of lights."""

    lights: Lights
    keys: Sequence[str]
    terms: int
    linear: bool = False
    pinv: dict[str, npt.NDArray[np.float32]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        keys = set(self.keys)
        key = next(iter(self.keys), "")
        try:
            if {"ptm", "ptm-lrgb"} & keys:
                key = next(k for k in self.keys if k.startswith("ptm"))
                pinv = ptm_pinv(ptm_design_matrix(self.lights))
                self.pinv["ptm-lrgb"] = pinv.astype(np.float32)
                self.pinv["ptm"] = (pinv * 255.0).astype(np.float32)
            if "hsh" in keys:
                key = "hsh"
                self.pinv["hsh"] = hsh_pinv(hsh_design_matrix(self.lights, self.terms), self.terms)
            if {"normals", "ward"} & keys:
                key = "normals" if "normals" in keys else "ward"
                check_lights(self.lights)
        except ValueError as err:
            raise ValueError(f"{key}: {err}") from None

    def solve(self, band: npt.NDArray[np.generic], keys: Sequence[str] | None = None,
              div: float = 1.0) -> dict[str, fb.Out]:
        """The float outputs of every requested model (or of ``keys`` among them) for one band
        (all of this solver's lights): ``band / div`` in 0–1, float32 or (photometric models
        only, values as stored) 8-/16-bit as decoded."""
        keys = self.keys if keys is None else keys
        floats = cast("npt.NDArray[np.float32]", band)  # what every model but those takes
        if div != 1.0 and (self.linear or set(keys) - {"normals", "ward"}):
            raise ValueError("only the photometric models, as stored, read a band as decoded")
        out: dict[str, fb.Out] = {}
        if "ptm" in keys:
            out["ptm"] = fb.ptm_rgb_band(floats, self.pinv["ptm"])
        if "ptm-lrgb" in keys:
            out["ptm-lrgb"] = fb.ptm_lrgb_band(floats, self.pinv["ptm-lrgb"])
        if "hsh" in keys:
            out["hsh"] = fb.hsh_band(floats, self.pinv["hsh"])
        if {"normals", "ward"} & set(keys):
            physical = srgb_to_linear(floats) if self.linear else band
            nrm = fb.normals_band(physical, self.lights,
                                  iterations=fb.IRLS_ITERATIONS if self.linear else 0, div=div,
                                  albedo="normals" in keys)  # Ward fits its own kd
            out["normals"] = nrm
            if "ward" in keys:
                normals = np.asarray(nrm["normals"], np.float32)
                out["ward"] = {**fb.ward_band(physical, self.lights, normals, div),
                               "normals": normals}
        return out
