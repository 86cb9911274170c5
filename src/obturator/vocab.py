"""The words the package accepts: every named choice, listed once.

Each vocabulary is a :data:`typing.Literal` (for type checkers and signatures)
and a tuple of its values (for validation, ``argparse`` choices, config files
and messages), the tuple derived from the Literal so the two cannot drift.

>>> METHODS
('auto', 'regularised', 'radau', 'rosenbrock', 'set-valued', 'moreau-jean')
>>> check_choice("spin_mode", "free", SPIN_MODES)
'free'
"""

from __future__ import annotations

from typing import Literal, get_args

from .errors import InputError

__all__ = [
    "CaseName",
    "SpinMode",
    "Method",
    "Formulation",
    "FrictionFamily",
    "TorqueName",
    "SpeedLawName",
    "DistKind",
    "NoiseModel",
    "CASE_NAMES",
    "SPIN_MODES",
    "METHODS",
    "SET_VALUED_METHODS",
    "FORMULATIONS",
    "FRICTION_FAMILIES",
    "TORQUE_MODELS",
    "SPEED_LAWS",
    "DIST_KINDS",
    "NOISE_MODELS",
    "check_choice",
]

#: Built-in cases: the two columns of the thesis's Table 1.
CaseName = Literal["spin-rig", "flight"]
#: Projectile spin: held constant (driven rig), free (axial momentum conserved),
#: or Appendix A's energy form.
SpinMode = Literal["constant", "free", "thesis-energy"]
#: Compiled integrators (``auto``: per case ``set-valued`` at low spin where that solver
#: takes the case, else ``regularised`` (:mod:`obturator.solve.dispatch`);
#: ``regularised``: the regularised law, DOP853 handing over to Radau IIA when stiff;
#: ``radau``, ``rosenbrock``: the regularised law with one method; ``set-valued``: the
#: event-driven stick-slip solver of the unregularised friction law; ``moreau-jean``:
#: first-order fixed-step time-stepping of the same law, a cross-check).
Method = Literal["auto", "regularised", "radau", "rosenbrock", "set-valued", "moreau-jean"]
#: State formulations of the equations of motion.
Formulation = Literal["quaternion", "euler"]
#: Regularisation families of the Coulomb friction magnitude.
FrictionFamily = Literal["algebraic", "tanh", "linear"]
#: Sliding-friction models: the thesis's laws (Eq. 61, Appendix A) or exact Coulomb contacts.
TorqueName = Literal["thesis", "coulomb"]
#: Slip-speed laws of the friction coefficient.
SpeedLawName = Literal["constant", "weakening", "strengthening"]
#: Monte Carlo input distributions.
DistKind = Literal["normal", "uniform", "lognormal", "truncnormal"]
#: Run-to-run noise of the validation likelihood: one SD per spin band (fitted) or one
#: pooled SD for all runs.
NoiseModel = Literal["band", "pooled"]

CASE_NAMES: tuple[str, ...] = get_args(CaseName)
SPIN_MODES: tuple[str, ...] = get_args(SpinMode)
METHODS: tuple[str, ...] = get_args(Method)
#: The methods of the set-valued friction law: no regularisation width.
SET_VALUED_METHODS: tuple[str, ...] = ("set-valued", "moreau-jean")
FORMULATIONS: tuple[str, ...] = get_args(Formulation)
FRICTION_FAMILIES: tuple[str, ...] = get_args(FrictionFamily)
TORQUE_MODELS: tuple[str, ...] = get_args(TorqueName)
SPEED_LAWS: tuple[str, ...] = get_args(SpeedLawName)
DIST_KINDS: tuple[str, ...] = get_args(DistKind)
NOISE_MODELS: tuple[str, ...] = get_args(NoiseModel)


def check_choice(field: str, value: object, allowed: tuple[str, ...]) -> str:
    """Return `value` if it is one of `allowed`, else raise :class:`InputError` naming them."""
    if value not in allowed:
        raise InputError(field, f"{value!r}; allowed: {', '.join(allowed)}")
    return value  # type: ignore[return-value]
