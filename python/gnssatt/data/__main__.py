"""``python -m gnssatt.data``: print the folder of the shipped GEONET pair (one line, for shell scripts)."""

from gnssatt.data import geonet_dir

print(geonet_dir())
