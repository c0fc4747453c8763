"""The simulator's vocabulary: the mode a block is in, the modes a scene went through, and the status bits its
integration sets, one meaning per code in every model (the rocking kernel, the general contact model, the
hand-off between them and the sampled kernels).

The enumerations name the codes; the module-level integers below them are the same values for the compiled
kernels (numba reads module globals as constants).
"""

from __future__ import annotations

from enum import IntEnum


class Mode(IntEnum):
    """The mode a block is in at an instant."""

    rest = 0
    slide = 1
    rock = 2
    slide_rock = 3
    flight = 4
    overturned = 5


class Verdict(IntEnum):
    """A sample's outcome in a plane, or over its planes (the sample kernels' ``verdict_out`` and ``outcome_out``)."""

    no_verdict = -1       # free flight before any overturning: the contact model holds no further
    stands = 0
    overturns = 1


class ContactMode(IntEnum):
    """Bits of an outcome's ``modes`` and of the output ``contact_modes``: the modes a scene went through."""

    slide = 1
    rock = 2
    slide_rock = 4
    free_flight = 8


class Status(IntEnum):
    """Bits of an outcome's ``status``: what the integration met (each bit one meaning in every model)."""

    chatter = 1           # rocking kernel: the event cap (max_events) reached; forced to rest
    ground_flight = 2     # the ground's g + a_v reached 0: contact lost (free flight begins there)
    step_underflow = 4    # rocking kernel: the step fell to the smallest that advances time (rules.min_advance)
    liftoff = 8           # the block's own motion took the contact force to 0 (f_z <= 0)
    friction = 16         # rocking kernel: the friction demand exceeded the block's stop_mu; stopped there
    tie_hold = 32         # tie rule 6 (rules), flat: events in a row at one instant; held at rest to the next sample
    step_cap = 64         # the step budget ran out: ended there, the verdict from the state reached
    painleve = 128        # contact model: slide-rock without a consistent normal force; the corner made to stick
    event_cap = 256       # contact model: MAX_EVENTS transitions; ended there, the verdict from the state reached
    tail_cap = 512        # contact model: the motion after the record outlasted MAX_TAIL_PERIODS; stopped, standing
    stalled = 1024        # contact model: tie rule 6 while not flat; ended there, the verdict from the state reached


REST, SLIDE, ROCK, SLIDE_ROCK, FLIGHT, OVERTURNED = (int(m) for m in Mode)
NO_VERDICT, STANDS, OVERTURNS = (int(v) for v in Verdict)
MODE_SLIDE, MODE_ROCK, MODE_SLIDE_ROCK, MODE_FLIGHT = (int(m) for m in ContactMode)
STATUS_CHATTER = int(Status.chatter)
STATUS_GROUND_FLIGHT = int(Status.ground_flight)
STATUS_STEP_UNDERFLOW = int(Status.step_underflow)
STATUS_LIFTOFF = int(Status.liftoff)
STATUS_FRICTION = int(Status.friction)
STATUS_TIE_HOLD = int(Status.tie_hold)
STATUS_STEP_CAP = int(Status.step_cap)
STATUS_PAINLEVE = int(Status.painleve)
STATUS_EVENT_CAP = int(Status.event_cap)
STATUS_TAIL_CAP = int(Status.tail_cap)
STATUS_STALLED = int(Status.stalled)
#: The status bits that end a scene before its end (the verdict is then the state's)
STATUS_ENDED = STATUS_EVENT_CAP | STATUS_STALLED | STATUS_STEP_CAP
