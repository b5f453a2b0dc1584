"""The cable models a run can use, by the name that chooses them (``CableOptions.cable_model``,
``rswarp cable --cable-model``). A new model is a ``CableSolver`` and its kernel, named here."""

from __future__ import annotations

from ..errors import InputError
from ..rsxml.model import Mechanism
from .cable_rod import CosseratRod
from .cable_solver import CableOptions, CableSolver, ContactMeshes

CABLE_MODELS: dict[str, type[CableSolver]] = {CosseratRod.kind: CosseratRod}


def cable_model(options: CableOptions) -> type[CableSolver]:
    """The model ``options`` names."""
    try:
        return CABLE_MODELS[options.cable_model]
    except KeyError:
        raise InputError(f"no cable model '{options.cable_model}' (models: {', '.join(CABLE_MODELS)})") from None


def make_solver(mech: Mechanism, options: CableOptions, meshes: ContactMeshes | None) -> CableSolver:
    """The solver of the mechanism's cables as ``options`` asks for it."""
    return cable_model(options)(mech, options, meshes)
