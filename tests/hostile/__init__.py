"""The hostile-input harness of issue 15: every public function driven with bad input (fixed categories and
hypothesis), mutated RINEX files, bad CLI arguments and LAMBDA against an independent search. The contract
checked is ``docs/robustness.md``; ``benches/python/hostile_inputs.py`` counts the outcomes."""
