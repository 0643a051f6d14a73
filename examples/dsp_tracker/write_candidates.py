"""Record the DSP's candidate lists of one scene for ``dsp_tracker`` (``main.c``).

    python examples/dsp_tracker/write_candidates.py --seed 0 --out seed0.dptbd
    make -C examples/dsp_tracker && examples/dsp_tracker/dsp_tracker seed0.dptbd

Runs the built-in scenario of ``dptbd run`` (seed ``--seed``) through the FPGA stage exactly
as ``dptbd run`` does, and writes, per segment, the list the DSP's tracker receives: each
candidate as the gateware's record payload (``dptbd.hw.candidate_layout``) plus the start
of its backtracked path. ``--expect`` also writes what ``dsp_tracker`` must print (the
Python model's confirmed tracks, :func:`format_tracks`), for a ``diff``.
"""

from __future__ import annotations

import argparse
import struct
import sys
from pathlib import Path

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig, Tracker
from dptbd.dsp.c_tracker import PARAM_NAMES, params_codes
from dptbd.dsp.record_header import record_layout_signature
from dptbd.hw.candidate_layout import pack_record

MAGIC = b"DPTBDCL1"
VERSION = 2


def scene_pipeline(seed: int = 0, association: dict | None = None):
    """The built-in scenario with ``seed`` through both stages, as ``dptbd run`` runs it.

    Returns
    -------
    (DPConfig, AssociationConfig, PipelineResult)
    """
    from dptbd.evaluation.run.job import run_job
    from dptbd.evaluation.run.scenario import default_scenario

    sc = default_scenario().replace(seed=seed, **({"association": association} if association else {}))
    sc.check()
    result = run_job(sc)                      # the main job, as dptbd run runs it
    return result.input.cfg, result.input.assoc, result.pipeline


def scene_lists(seed: int = 0, association: dict | None = None):
    """The lists the DSP's tracker receives in :func:`scene_pipeline`.

    Returns
    -------
    (DPConfig, AssociationConfig, dict, list of numpy.ndarray)
        The DP configuration, the association's, the tracker's keyword arguments and the
        per-segment :data:`~dptbd.dsp.association.CANDIDATE_DTYPE` lists.
    """
    cfg, assoc, res = scene_pipeline(seed, association)
    kwargs = dict(segment_frames=cfg.segment_frames, segment_stride=cfg.segment_stride,
                  height=cfg.height, width=cfg.width, radius=cfg.radius)
    return cfg, assoc, kwargs, res.candidates


def candidate_file_bytes(cfg: DPConfig, assoc: AssociationConfig, tracker_kwargs: dict,
                         lists: list) -> bytes:
    """The file ``dsp_tracker`` reads (format in ``main.c``)."""
    codes = params_codes(Tracker(assoc, **tracker_kwargs), tracker_kwargs.get("radius", 1))
    out = [MAGIC, struct.pack("<I", VERSION),
           struct.pack("<9I", *record_layout_signature(cfg)),
           struct.pack("<4I", assoc.capacity, assoc.max_candidates, assoc.max_points,
                       assoc.output_capacity),
           struct.pack(f"<{len(PARAM_NAMES)}i", *(codes[name] for name in PARAM_NAMES)), struct.pack("<I", len(lists))]
    for cands in lists:
        out.append(struct.pack("<I", len(cands)))
        for c in cands:
            word = pack_record(cfg, int(c["row"]), int(c["col"]), int(c["energy"]),
                               int(c["direction"]))
            out.append(struct.pack("<QHHB", word, int(c["row0"]), int(c["col0"]), int(c["path"])))
    return b"".join(out)


def format_tracks(tracker: Tracker) -> str:
    """What ``dsp_tracker`` prints for a tracker's state (the host-side read-out)."""
    st = tracker.stats
    extra = getattr(tracker, "input_counters", {})
    tracks = tracker.confirmed_tracks()
    lines = [f"segments {st['segments']}, candidates {st['candidates']}, started {st['started']}, "
             f"confirmed {st['confirmed']}, deleted {st['deleted']}, "
             f"clipped {extra.get('clipped_candidates', 0)}, "
             f"rejected {extra.get('rejected_candidates', 0)}",
             f"confirmed tracks: {len(tracks)}"]
    for tr in tracks:
        lines.append(f"track {tr.id}: segments {tr.first_segment}-{tr.last_segment}, confirmed in "
                     f"{tr.confirm_segment}, hits {tr.hits}, {'alive' if tr.alive else 'ended'}")
        for p in tr.points:
            lines.append(f"  segment {int(p['seg'])}: row {int(p['row'])} col {int(p['col'])} "
                         f"E {int(p['energy'])}")
    return "\n".join(lines) + "\n"


def python_output(assoc: AssociationConfig, tracker_kwargs: dict, lists: list) -> str:
    """:func:`format_tracks` of the Python model after every list."""
    tracker = Tracker(assoc, **tracker_kwargs)
    for cands in lists:
        tracker.step(cands)
    return format_tracks(tracker)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0, help="scene seed (default 0)")
    ap.add_argument("--out", required=True, help="candidate file to write")
    ap.add_argument("--expect", help="also write the Python model's output here")
    args = ap.parse_args(argv)
    cfg, assoc, kwargs, lists = scene_lists(args.seed)
    Path(args.out).write_bytes(candidate_file_bytes(cfg, assoc, kwargs, lists))
    if args.expect:
        Path(args.expect).write_text(python_output(assoc, kwargs, lists))
    print(f"wrote {args.out}: {len(lists)} segments, "
          f"{sum(len(c) for c in lists)} candidates", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
