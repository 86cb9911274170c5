"""Running many tasks of a study: where, in which chunks, resumably, with progress.

Every study (sweep, Monte Carlo, envelope and its probability, sensitivity and
optimisation studies, validation, reproduction) runs its tasks through one
:class:`Runner`:

* :mod:`.runner`: :class:`Runner` (workers, scheduler, chunking, store, progress),
  ``Runner.run(job, results, ...)`` and ``Runner.map(fn, tasks)``;
* :mod:`.chunks`: :class:`Job` (what a chunk computes), the chunking and the timed probe;
* :mod:`.pools`: in this process or a local process pool (:func:`mp_context`,
  :func:`die_with_parent`, :func:`gc_frozen`); :mod:`.cluster`: a Dask cluster;
* :mod:`.store`: the resume store (a locked sidecar of CRC-checked records) and atomic
  files; :mod:`.digest`: the study digest and task keys;
* :mod:`.results`: the content-addressed results of ``Runner.map``;
* :mod:`.progress`: the one progress reporter (a bar, plain lines, or nothing).

``runs`` knows no study: studies import it, never the reverse.
"""

from .chunks import Job
from .digest import study_digest, task_key
from .pools import default_workers, die_with_parent, gc_frozen, mp_context
from .progress import Progress
from .runner import Results, RunInfo, Runner
from .store import ResumeStore, sidecar_path

__all__ = [
    "Job",
    "Progress",
    "Results",
    "ResumeStore",
    "RunInfo",
    "Runner",
    "default_workers",
    "die_with_parent",
    "gc_frozen",
    "mp_context",
    "sidecar_path",
    "study_digest",
    "task_key",
]
