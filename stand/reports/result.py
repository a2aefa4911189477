"""``stand.report``'s answer as a result object (:class:`stand.io.result.Result`): :class:`Report`."""
from __future__ import annotations

from stand.io.numbers import with_uncertainty
from stand.io.result import Result

__all__ = ["Report"]


class Report(Result):
    """A balancing-quality report (:func:`stand.reports.balancing.balancing_report`;
    docs/reports.md gives every key with its unit, docs/results.md the object).

    The sections are attributes: ``report`` (kind, format version, input),
    ``header`` (scene, masses, capacity, speeds), ``balancing_quality`` (initial and
    residual unbalance, ISO 21940-11 grade, reduction), ``dynamics`` (natural
    frequency, critical speeds, regimes, settling), ``warnings``, ``notes``;
    :attr:`passed` is the ISO 21940-11 verdict (None when not evaluated).  Tables for
    :meth:`to_frame`: ``"warnings"``, ``"dynamics.critical_speeds"``,
    ``"dynamics.regime_timeline"``, ``"dynamics.settling"``, ``"balancing_quality.seed_criteria"``.
    The picture: initial and residual unbalance against the permissible residual.
    """

    _title = "balancing-quality report"

    @property
    def passed(self):
        """The ISO 21940-11 verdict: True, False, or None when it was not evaluated."""
        return ((self.get("balancing_quality") or {}).get("iso_21940_11") or {}).get("passed")

    def _summary(self) -> list:
        q = self.get("balancing_quality") or {}
        head = self.get("header") or {}
        out = [("recording", repr((self.get("report") or {}).get("recording"))),
               ("scene_name", repr(head.get("scene_name")))]
        for k in ("initial_unbalance_gmm", "residual_unbalance_gmm"):
            v = q.get(k)
            out.append((k, with_uncertainty(v, q.get(k + "_std"), "g·mm")))
        out += [("passed", repr(self.passed)), ("warnings", str(len(self.get("warnings") or [])))]
        return out

    def _draw(self, ax) -> None:
        q = self.get("balancing_quality") or {}
        iso = q.get("iso_21940_11") or {}
        names = ["initial", "residual"]
        values = [q.get("initial_unbalance_gmm") or 0.0, q.get("residual_unbalance_gmm") or 0.0]
        ax.bar(names, values, color=["C7", "C0"])
        if iso.get("permissible_residual_gmm") is not None:
            ax.axhline(iso["permissible_residual_gmm"], color="C3", ls="--", lw=1,
                       label=f"permissible (G {iso.get('required_grade_mm_s', 0):g})")
            ax.legend(loc="upper right")
        ax.set_ylabel("unbalance [g·mm]")
        ax.set_title(f"balancing quality: {(self.get('header') or {}).get('scene_name') or ''}",
                     fontsize=9)
