"""A study's results as plain arrays: :class:`StudyTable`, and its NetCDF file.

A sweep or Monte Carlo study ends as a few numeric arrays over its dimensions with CF
attributes. :class:`StudyTable` holds them in the form :class:`xarray.Dataset` takes
(``name -> (dims, values, attrs)``), so the Dataset the API returns is one call away
(:meth:`StudyTable.to_dataset`), and the command line writes its NetCDF and CSV files
from the arrays without building one.

Why the NetCDF file is written here with :mod:`netCDF4` rather than by
:meth:`xarray.Dataset.to_netcdf`: xarray's first Dataset and first write probe for
dask (with dask installed they import ``dask.array`` and ``dask.distributed``), and
the command line has nothing else to do with xarray. That import is processor time
beside the workers of every ``obturator sweep`` and ``obturator montecarlo``
(``docs/benchmarks.md``, history, "A study's files without xarray"). The file is
the one xarray would write for the same Dataset: dimension coordinates, scalar
coordinates listed in each data variable's CF ``coordinates`` attribute, NaN as the
``_FillValue`` of floating-point variables; ``tests/sweeps/test_table.py`` opens it
with xarray and compares it with :meth:`StudyTable.to_dataset`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from numbers import Number
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import xarray

__all__ = ["StudyTable", "write_table_netcdf"]

#: ``name -> (dims, values, attrs)``, the form :class:`xarray.Dataset` takes.
Variables = Mapping[str, tuple[Any, Any, Mapping[str, Any]]]


@dataclass(frozen=True)
class StudyTable:
    """A study's variables, coordinates and attributes as numpy arrays.

    Attributes
    ----------
    data : mapping
        Data variables, ``name -> (dims, values, attrs)`` (``dims`` a name or a tuple
        of names; ``()`` for a scalar).
    coords : mapping
        Coordinates in the same form: dimension coordinates and scalar coordinates
        (the study's fixed parameters).
    attrs : dict
        Global attributes (str, numbers, numpy arrays).
    """

    data: Variables
    coords: Variables
    attrs: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def of(cls, results: StudyTable | xarray.Dataset) -> StudyTable:
        """`results` as a table: a table as it is, a Dataset's variables, coordinates and
        attributes (their numpy values), so that the summaries and the CSV writer read
        either the same way."""
        if isinstance(results, StudyTable):
            return results

        def entries(variables: Any) -> dict[str, Any]:
            return {k: (v.dims, v.values, dict(v.attrs)) for k, v in variables.items()}

        return cls(entries(results.data_vars), entries(results.coords), dict(results.attrs))

    def values(self, name: str) -> np.ndarray:
        """The values of the data variable or coordinate `name`."""
        return np.asarray(self._entry(name)[1])

    def dims(self, name: str) -> tuple[str, ...]:
        """The dimensions of the data variable or coordinate `name`."""
        dims = self._entry(name)[0]
        return (dims,) if isinstance(dims, str) else tuple(dims)

    def with_attrs(self, **attrs: Any) -> StudyTable:
        """A copy with `attrs` added to the global attributes."""
        return StudyTable(self.data, self.coords, {**self.attrs, **attrs})

    def to_dataset(self) -> xarray.Dataset:
        """The study as an :class:`xarray.Dataset` (the form the API returns)."""
        import xarray as xr

        return xr.Dataset(dict(self.data), coords=dict(self.coords), attrs=dict(self.attrs))

    def _entry(self, name: str) -> tuple[Any, Any, Mapping[str, Any]]:
        if name in self.data:
            return self.data[name]
        return self.coords[name]


def write_table_netcdf(table: StudyTable, path: str | os.PathLike[str]) -> None:
    """Write `table` to a NetCDF-4 file at `path` (not atomic: the caller renames).

    Numeric variables only (floats get NaN as ``_FillValue``, as xarray writes them);
    non-dimension coordinates are named in each data variable's ``coordinates``
    attribute, so xarray reads them back as coordinates.
    """
    import netCDF4

    sizes: dict[str, int] = {}
    for name in (*table.coords, *table.data):
        for dim, n in zip(table.dims(name), table.values(name).shape, strict=True):
            if sizes.setdefault(dim, n) != n:
                raise ValueError(f"dimension {dim!r} has sizes {sizes[dim]} and {n}")
    aux = [n for n in table.coords if table.dims(n) != (n,)]
    with netCDF4.Dataset(path, "w", format="NETCDF4") as nc:
        for dim, n in sizes.items():
            nc.createDimension(dim, n)
        for kind, variables in (("data", table.data), ("coords", table.coords)):
            for name, (_, _, attrs) in variables.items():
                values = table.values(name)
                if values.dtype.kind not in "fiu":
                    raise TypeError(f"{name}: only numeric variables are written ({values.dtype})")
                fill = np.nan if values.dtype.kind == "f" else None
                var = nc.createVariable(name, values.dtype, table.dims(name), fill_value=fill)
                var.set_auto_maskandscale(False)
                var[...] = values
                extra = {"coordinates": " ".join(aux)} if kind == "data" and aux else {}
                var.setncatts({k: _attribute(name, k, v) for k, v in {**attrs, **extra}.items()})
        nc.setncatts({k: _attribute("global", k, v) for k, v in table.attrs.items()})


def _attribute(owner: str, key: str, value: Any) -> Any:
    """`value` as a NetCDF attribute (the types xarray accepts)."""
    if isinstance(value, str | np.ndarray | np.number | bytes):
        return value
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, Number):
        return value
    if isinstance(value, list | tuple):
        return np.asarray(value)
    raise TypeError(f"{owner}: attribute {key!r} of type {type(value).__name__} cannot be written")
