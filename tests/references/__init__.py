"""Independent numpy implementations that tests and benches compare the Rust core against.

They are not part of the package (the wheel does not contain them): tests import them as ``references.*``
(pytest puts ``tests/`` on ``sys.path``), benches after adding ``tests/`` to ``sys.path``.
"""
