"""Deterministic verification of generated instructions: task preservation, scene grounding, pattern structure."""

from builders.verification.checks import CHECKS, Context, checks_for, verify

__all__ = ["CHECKS", "Context", "checks_for", "verify"]
