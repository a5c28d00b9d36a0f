"""TALK-Dem: robot task planning under dementia-associated communication."""

__version__ = "0.1.0"
__all__ = ["__version__"]
