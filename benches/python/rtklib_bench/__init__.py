"""The parts of ``benches/python/rtklib_compare.py``: RTKLIB 2.4.3 and ``gnssatt attitude`` side by side
(that script's docstring says what it measures and how)."""
