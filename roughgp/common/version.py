"""The version of roughgp, in one place below every module that records it: ``roughgp
--version``, the model file (``roughgp_version``) and the ``.x3p`` files roughgp writes; the
package face re-exports it as ``roughgp.__version__``."""

__all__ = ["VERSION"]

VERSION = "0.1.0"  #: the version of roughgp (pyproject.toml's)
