# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
The result of the identification's step 3 (pre-sliding parameters) as a frozen record.

:class:`PreslidingStep` holds what step 3 did (``status``), why it did not fit
(``reason``, ``why``, ``advice``) and the per-model results; :meth:`PreslidingStep.to_dict`
builds the ``presliding`` entry of ``identification.json`` (the only place its keys exist).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ['PreslidingStep']


@dataclass(frozen=True)
class PreslidingStep:
    """
    What step 3 (the pre-sliding fit) did.

    Parameters
    ----------
    status : {'done', 'skipped', 'failed'}
        ``'done'``: it ran (each model's own ``status`` says whether its fit was kept).
    reason : str or None
        Why it was skipped or failed.
    note : str or None
        What a failure leaves (the structure's pre-sliding values).
    models : dict or None
        Per model (``'lugre'``, ``'gms'``) its fit: ``status``, ``params``, ``stderr``,
        ``rel_stderr``, ``report``, ...; None when skipped.
    excitation : dict or None
        Of a failed or rejected fit: what the recordings excite
        (:func:`~friction_joint.identification.presliding.presliding_excitation`).
    why : str or None
        Of a failed or rejected fit: why, in plain words.
    advice : str or None
        Of a failed or rejected fit: what to record.

    """

    status: str
    reason: str | None = None
    note: str | None = None
    models: dict[str, dict[str, Any]] | None = None
    excitation: dict[str, Any] | None = None
    why: str | None = None
    advice: str | None = None

    @property
    def explained(self) -> bool:
        """Return whether ``why`` and ``advice`` say why a failure or rejection did not fit."""
        return self.excitation is not None

    def to_dict(self) -> dict[str, Any]:
        """Return the ``presliding`` entry of ``identification.json``."""
        out: dict[str, Any] = {'status': self.status}
        if self.reason is not None:
            out['reason'] = self.reason
        if self.note is not None:
            out['note'] = self.note
        if self.models is not None:
            out['models'] = self.models
        if self.explained:
            out.update(excitation=self.excitation, why=self.why, advice=self.advice)
        return out
