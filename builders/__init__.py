"""The pipeline that makes the TALK-Dem dataset from the REI-Bench seed pool."""
