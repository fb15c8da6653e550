"""Warnings a test's scenes give by design, said where the scenes are made.

exdex issues a :class:`exdex.PhysicsWarning` for every finding of a result
(an impact on a stop, a slide past the pad, the pads leaving the body
outline, a soft problem counted by the solver) and a
:class:`exdex.GripperJumpWarning` for a jump of the gripper's velocity. Many
tests make such scenes on purpose (random scenes, objects dropped onto
stops); their warnings are part of the scene, not news. A test says which
kinds its scenes give by design with the marker

    @pytest.mark.warns_by_design("impact", "outline")

(or a module's ``pytestmark``), or around a block with
``with by_design("impact"):``. Warnings of those kinds are then recorded and
dropped; every other warning is issued again unchanged (same category,
message, file and line), so an unexpected kind still reaches the log and
pytest's filters. A test that is *about* a warning asserts it with
``pytest.warns`` instead.

Kinds: the ``kind`` of a PhysicsWarning ("impact", "pad", "outline",
"solver"; "noisy_log" for an exdex.NoisyLogWarning, "plausibility" for an
exdex.PlausibilityWarning) and "jump" for a GripperJumpWarning.
"""
from __future__ import annotations

import contextlib
import warnings

import exdex

KINDS = ("impact", "pad", "outline", "solver", "jump", "noisy_log", "plausibility")

#: Every kind: random scenes (the zoo) may give any of them.
ALL = KINDS


def kind_of(message):
    """The kind of a warning instance, or None for a warning exdex does not classify."""
    if isinstance(message, exdex.GripperJumpWarning):
        return "jump"
    if isinstance(message, exdex.PhysicsWarning):
        return message.kind
    return None


def check_kinds(kinds):
    bad = [k for k in kinds if k not in KINDS]
    if bad or not kinds:
        raise ValueError(f"warns_by_design takes kinds out of {KINDS}, got {kinds!r}")
    return frozenset(kinds)


@contextlib.contextmanager
def by_design(*kinds):
    """Drop the warnings of ``kinds`` raised inside the block (recorded in the
    list the context yields); issue every other warning again."""
    wanted = check_kinds(kinds)
    dropped = []
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        yield dropped
    for w in rec:
        if kind_of(w.message) in wanted:
            dropped.append(w)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
