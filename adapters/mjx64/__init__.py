"""MJX in float64 (JAX's x64 mode): the ``mjx`` adapter and settings, judged at float64."""

from ..mjx import RECORD_64 as RECORD
from ..mjx import MjxSettings

__all__ = ["RECORD", "MjxSettings"]
