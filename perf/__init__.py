"""Performance benchmarks (timings of this package, not TALK-Dem results) run by `make bench`: each module prints
ratios measured side by side in one run."""
