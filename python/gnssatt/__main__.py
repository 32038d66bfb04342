"""``python -m gnssatt``: the same as the ``gnssatt`` command."""

from gnssatt.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
