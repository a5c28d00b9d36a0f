"""Benchmarks run by `make bench`: each module prints ratios measured side by side in one run."""
