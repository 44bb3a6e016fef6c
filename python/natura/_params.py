"""The parameter objects shared by natura's modules (a noise basis, a wave
spectrum, foam): a kind and keyword parameters, as the native module reads
them."""

from __future__ import annotations

from typing import Any, Dict


class Params:
    """A kind of model with its keyword parameters."""

    kind: str = ""

    def __init__(self, **params: Any) -> None:
        self.params: Dict[str, Any] = params

    def spec(self) -> Dict[str, Any]:
        """The parameter dictionary natura's native module reads."""
        return {"kind": self.kind, **self.params}

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({args})"
