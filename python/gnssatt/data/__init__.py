"""Recorded data shipped with the package, so that examples, tests and reproductions need nothing else.

``rtklib_geonet_0759_3040/``: the GEONET pair (two stations 3.3 km apart, RINEX 2.10, GPS, 120 epochs) with
its provenance ``README.md`` and licence excerpt. ``python -m gnssatt.data`` prints that folder, for shell
use: ``gnssatt attitude --obs "$(python -m gnssatt.data)/07590920.05o" ...``.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["geonet_dir"]


def geonet_dir() -> Path:
    """Folder of the shipped GEONET pair (stations 0759 and 3040, 2005-04-02 00:00-00:59:30 GPST).

    Returns
    -------
    pathlib.Path
        Folder holding ``07590920.05o``, ``07590920.05n``, ``30400920.05o``, ``30400920.05n`` (RINEX 2.10
        observation and GPS navigation files), ``LICENSE.RTKLIB-excerpt.txt`` and ``README.md``
        (provenance; cite GSI GEONET).

    Examples
    --------
    >>> from gnssatt.data import geonet_dir
    >>> from gnssatt.rinex import read_obs
    >>> len(read_obs(geonet_dir() / "07590920.05o").time)
    120
    """
    # gnssatt carries a compiled extension, which cannot be imported from a zip archive, so the package and
    # its data always lie in a real folder and the resource is a plain path.
    return Path(str(resources.files(__name__).joinpath("rtklib_geonet_0759_3040")))
