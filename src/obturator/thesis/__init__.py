"""Reproducing the thesis: its figure studies, the checked numbers and the report.

* :mod:`.histories`: theta(t) studies of Figs. 9-17 and 32-37;
* :mod:`.opening_times`: t_cr curves of Figs. 38-43 and the t_cr minimum;
* :mod:`.common`: what the studies share (solver attributes, horizons);
* :mod:`.rows`: the comparison table, a loop over the printed-values data file;
* :mod:`.captions`: figure captions with the thesis's pages;
* :mod:`.explorer`: the report's interactive t_cr explorer;
* :mod:`.render`: Markdown and HTML;
* :mod:`.reproduce`: the driver behind ``obturator reproduce``.

The studies return labelled :class:`xarray.Dataset` objects and plot nothing;
:mod:`obturator.plotting` draws them.
"""

from ..reference import CAPTION_SHEAR_CONSTANT, THESIS_MU_S
from .common import solver_attrs
from .histories import (
    couette_shear_constant,
    couette_study,
    density_study,
    exact_vs_approximate,
    flight_and_rig_study,
    hole_radius_study,
    rig_spin_study,
)
from .opening_times import fig43_study, opening_time_minimum, opening_time_vs_spin
from .reproduce import ReproduceResult, reproduce
from .rows import Row, checkable_rows

__all__ = [
    "CAPTION_SHEAR_CONSTANT",
    "THESIS_MU_S",
    "ReproduceResult",
    "Row",
    "checkable_rows",
    "couette_shear_constant",
    "couette_study",
    "density_study",
    "exact_vs_approximate",
    "fig43_study",
    "flight_and_rig_study",
    "hole_radius_study",
    "opening_time_minimum",
    "opening_time_vs_spin",
    "reproduce",
    "rig_spin_study",
    "solver_attrs",
]
