"""The cable models a run can use, by the name that chooses them (``CableOptions.cable_model``,
``rswarp cable --cable-model``). A new model is a ``CableSolver`` and its kernel, named here."""

from __future__ import annotations

from ...errors import InputError
from ...rsxml.model import Mechanism
from .rod import CosseratRod
from .solver import CableOptions, CableSolver, ContactMeshes

CABLE_MODELS: dict[str, type[CableSolver]] = {CosseratRod.kind: CosseratRod}


def cable_model(options: CableOptions) -> type[CableSolver]:
    """The model ``options`` names."""
    try:
        return CABLE_MODELS[options.cable_model]
    except KeyError:
        raise InputError(f"no cable model '{options.cable_model}' (models: {', '.join(CABLE_MODELS)})") from None


def make_solver(mech: Mechanism, options: CableOptions, meshes: ContactMeshes | None,
                designs: tuple[Mechanism, ...] = ()) -> CableSolver:
    """The solver of the mechanism's cables as ``options`` asks for it; with ``designs``, environment
    e runs ``designs[e]`` (a model that takes designs: ``CableSolver.designs_at_once``)."""
    model = cable_model(options)
    if not designs:
        return model(mech, options, meshes)
    if not model.designs_at_once:
        raise InputError(f"cable model '{options.cable_model}' runs one design at a time; a sweep needs one that "
                         f"runs many ({', '.join(k for k, m in CABLE_MODELS.items() if m.designs_at_once)})")
    return model(mech, options, meshes, designs=designs)
