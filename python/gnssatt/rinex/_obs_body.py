"""The epochs of a RINEX observation file, read by the Rust core (``gnssatt_core::rinex``) from the
decompressed file and the layout its header gives: epoch lines, satellite lists, event records and the
16-column observation fields, checked (file, line, expected, got) and put into dense arrays.
"""

from __future__ import annotations

from gnssatt import _core
from gnssatt.rinex._fields import HEADER_LABELS, split_lines
from gnssatt.rinex._obs_header import ObsHeader, used_code

__all__ = ["header_lines", "read_body"]

_END = b"END OF HEADER"


def header_lines(raw: bytes) -> list[str]:
    """The lines of ``raw`` up to its ``END OF HEADER`` line (every line where it has none), so that the
    header is parsed without decoding the observations."""
    start = 0
    while (k := raw.find(_END, start)) >= 0:
        end = raw.find(b"\n", k)
        end = len(raw) if end < 0 else end
        line = split_lines(raw[raw.rfind(b"\n", 0, k) + 1 : end])[0]
        if line and line[0][60:80].strip() == _END.decode():
            return split_lines(raw[:end])[0]
        start = k + 1
    return split_lines(raw)[0]


def read_body(
    path: str, raw: bytes, first_line: int, hdr: ObsHeader, codes: tuple[str, ...], max_cells: int
) -> _core.ObsBody:
    """The epochs of ``raw`` from line ``first_line`` (0-based), their values on the axis ``codes``.

    Raises
    ------
    RinexError
        The first record that breaks the RINEX rules (the structure of the whole body first, then the
        fields), or more than ``max_cells`` epochs x satellites x codes.
    """
    v3 = hdr.version >= 3
    # RINEX 2: one layout for every system of the file
    systems = hdr.layout.items() if v3 else [("*", next(iter(hdr.layout.values())))]
    layouts = []
    for key, columns in systems:
        keep = [k for k, c in enumerate(columns) if used_code(c, v3)]
        factors = hdr.scale.get(key, {})
        layouts.append(
            (
                key,
                len(columns),
                keep,
                [codes.index(columns[k]) for k in keep],
                [float(factors.get(columns[k], factors.get("*", 1))) for k in keep],
            )
        )
    return _core.rinex_obs_body(
        path,
        raw,
        first_line,
        v3,
        hdr.system if hdr.system != "M" else "G",
        layouts,
        len(codes),
        sorted(HEADER_LABELS),
        max_cells,
    )
