"""``stand.theory``'s answer as a result object (:class:`stand.io.result.Result`): :class:`Theory`."""
from __future__ import annotations

from stand.io.result import Result

__all__ = ["Theory"]


class Theory(Result):
    """What the theory says of a scene (:func:`stand.theories.scene.theory`; docs/results.md).

    The keys are those of ``stand theory --json``; ``kind`` says which theory applied:

    * ``"chapter5"`` -- the planar rotor with balls or pendulums: ``natural_frequency_hz``,
      ``operating_speed_hz``, ``stable_bands`` (``from_hz``, ``to_hz``, ``motions``),
      ``critical_speeds_hz`` (``hz``, ``motion``, ``kind``), ``qp`` (stuck balls);
    * ``"structure"`` -- any rotor: ``natural_frequencies_hz_at_rest``,
      ``engineering_criterion`` (per plane: ``critical_speeds_hz``, ``working_ranges_hz``),
      ``campbell`` (``speed_hz``, ``frequencies_hz``), ``weight_models``;
    * ``"book_model"`` -- a book weight model: ``steady_motions``, ``balancing_efficiency``.

    ``not_applicable`` lists what was left out and why.  :attr:`natural_frequencies_hz`
    names the natural frequencies [Hz] whatever the kind.  Tables for :meth:`to_frame`:
    ``"stable_bands"``, ``"critical_speeds_hz"``, ``"steady_motions"``, ``"campbell"``.
    The picture: the speed bands and critical speeds (chapter 5), the Campbell diagram
    with the critical speeds (structures), the steady motions' deflections (book models).
    """

    _title = "theory"
    _summary_keys = ("kind", "scene", "natural_frequency_hz", "natural_frequencies_hz_at_rest",
                    "operating_speed_hz", "type")

    @property
    def natural_frequencies_hz(self) -> list:
        """The scene's natural frequencies [Hz]: at rest for a structure, f0 for chapter 5
        (empty for a book model, whose speeds are in omega0)."""
        if "natural_frequencies_hz_at_rest" in self:
            return list(self["natural_frequencies_hz_at_rest"])
        f0 = self.get("natural_frequency_hz")
        return [] if f0 is None else [f0]

    def _draw(self, ax) -> None:
        doc = self.to_dict()
        kind = doc.get("kind")
        if kind == "chapter5":
            _draw_bands(ax, doc)
        elif kind == "structure":
            _draw_campbell(ax, doc)
        else:
            _draw_steady(ax, doc)
        ax.set_title(f"theory of {doc.get('scene', '')} ({kind})", fontsize=9)


def _draw_bands(ax, doc) -> None:
    """Chapter 5: each speed band's stable motions as a span, the critical speeds as lines."""
    for k, b in enumerate(doc.get("stable_bands", [])):
        ax.axvspan(b["from_hz"], b["to_hz"], color=f"C{k % 10}", alpha=0.25)
        ax.text(0.5 * (b["from_hz"] + b["to_hz"]), 0.5, "\n".join(b["motions"]) or "-",
                ha="center", va="center", fontsize=7, transform=ax.get_xaxis_transform())
    for c in doc.get("critical_speeds_hz", []):
        ax.axvline(c["hz"], color="k", lw=0.8, ls="--")
    if doc.get("operating_speed_hz") is not None:
        ax.axvline(doc["operating_speed_hz"], color="C3", lw=1.2, label="operating speed")
        ax.legend(loc="upper right")
    ax.set_xlabel("speed [rev/s]")
    ax.set_yticks([])


def _draw_campbell(ax, doc) -> None:
    """A structure: natural frequencies against speed, the 1X line and the critical speeds."""
    camp = doc.get("campbell") or {}
    s = camp.get("speed_hz") or []
    f = camp.get("frequencies_hz") or []
    if s and f:
        ax.plot(s, f, lw=0.9)
        ax.plot(s, s, "k:", lw=0.8, label="1X")
    for p, d in (doc.get("engineering_criterion") or {}).items():
        for c in d.get("critical_speeds_hz", []):
            ax.plot([c], [c], "o", color="C3")
    ax.set_xlabel("speed [rev/s]")
    ax.set_ylabel("natural frequency [Hz]")
    if s and f:
        ax.legend(loc="upper left")


def _draw_steady(ax, doc) -> None:
    """A book model: the deflection of each steady motion, stable ones filled."""
    ms = doc.get("steady_motions", [])
    labels = [str(m.get("label") or m.get("kind")) for m in ms]
    dev = [m.get("deflection") or 0.0 for m in ms]
    ax.bar(range(len(ms)), dev, color=["C2" if m.get("stable") else "C7" for m in ms])
    ax.set_xticks(list(range(len(ms))), labels)
    ax.set_xlabel("steady motion (green: stable)")
    ax.set_ylabel("deflection (dimensionless)")
