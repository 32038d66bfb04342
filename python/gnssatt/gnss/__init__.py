"""Front of the Rust observation engine (``rust/core/src/gnss``): recorded observations gathered into sessions
(:mod:`~gnssatt.gnss.session_input`) and solved for attitude or baselines (:mod:`~gnssatt.gnss.attitude`).

Reading and writing the files is :mod:`gnssatt.rinex`'s; this package only prepares and solves. Nothing is
imported here (the engine loads on first use). Layers: ``docs/architecture.md``.
"""
