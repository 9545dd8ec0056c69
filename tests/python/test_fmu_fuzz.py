"""Random FMI call sequences on one instance (issue 13's fuzz suite), as
hypothesis's stateful testing draws them: inputs and parameters with any
value (NaN, infinities, huge, tiny), steps of any size from the right or a
wrong time, calls in the wrong mode, states saved, serialized, restored,
reset, terminate. What must hold after every call:

- the host survives and every status is one FMI defines (0..4), never
  Fatal;
- a call refused for its arguments or its mode says so and changes nothing
  a later call could see: a Discarded or refused doStep leaves every output
  and the saved state's bytes as they were;
- the mode follows the FMI 2.0 state machine: stepping works only after
  initialisation and before fmi2Terminate; fmi2Reset starts again;
- no silent error: every Discard and Error comes with a log line;
- every output after an accepted step is finite;
- a restored state gives the outputs it was saved with, and saves to the
  same bytes (a rollback mismatch otherwise).

The test prints the tally: calls, steps taken and discarded, errors (each
logged), rollbacks compared.

Bounded for CI (FUZZ_EXAMPLES, default 25 sequences of up to 25 calls);
`scripts/fuzz_fmu.sh` runs a long campaign."""

import math
import os

from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule

from conftest import _MESSAGES, _callbacks

EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "25"))
STEPS = int(os.environ.get("FUZZ_STEPS", "25"))

ODD = [math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-310, 0.0, -0.0]
values = st.one_of(st.sampled_from(ODD), st.floats(-0.2, 0.2), st.floats(allow_nan=True, allow_infinity=True))
steps = st.one_of(st.sampled_from([0.0, -1.0, 1e-300, 1e-9, 1e300, math.nan, math.inf]), st.floats(1e-4, 1.0))


TALLY = dict(sequences=0, calls=0, steps=0, discarded=0, errors=0, rollbacks=0)


def call(f, *args):
    """A call's status: 0 when fmpy returns, the status it raised with.
    A Discard or an Error must have said why in the log."""
    said = len(_MESSAGES["fuzz"])
    try:
        f(*args)
        status = 0
    except FMICallException as e:
        status = e.status
    TALLY["calls"] += 1
    if status in (2, 3):
        TALLY["errors" if status == 3 else "discarded"] += 1
        assert len(_MESSAGES["fuzz"]) > said, f"{f.__name__} returned {status} without a log line"
    return status


class FmiSequences(RuleBasedStateMachine):
    folder = None  # set by the test

    @initialize(ready=st.integers(0, 3))
    def start(self, ready):
        md = read_model_description(self.folder + "/modelDescription.xml")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.inputs = [v.name for v in md.modelVariables if v.causality == "input"]
        self.params = [v.name for v in md.modelVariables if v.causality == "parameter" and v.type == "Real"]
        self.outputs = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=self.folder,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="fuzz",
        )
        _MESSAGES["fuzz"] = []
        self.fmu.instantiate(loggingOn=False, callbacks=_callbacks())
        TALLY["sequences"] += 1
        self.mode = "instantiated"
        self.t = 0.0
        self.saved = None
        if ready:
            # Three sequences in four start initialised, so that most reach
            # the solver; the others start where FMI does.
            self.initialise()

    def teardown(self):
        if getattr(self, "fmu", None) is not None:
            call(self.fmu.terminate)
            self.fmu.freeInstance()
            self.fmu = None

    def status_ok(self, s):
        assert s in (0, 1, 2, 3), f"status {s}"

    def snapshot(self):
        return self.fmu.getReal(self.outputs)

    @rule()
    def initialise(self):
        s1 = call(self.fmu.setupExperiment, None, 0.0)
        s2 = call(self.fmu.enterInitializationMode)
        s3 = call(self.fmu.exitInitializationMode)
        for s in (s1, s2, s3):
            self.status_ok(s)
        if self.mode == "instantiated":
            assert (s1, s2) == (0, 0)
        elif self.mode in ("stepping", "terminated"):
            # Wrong mode for initialisation: refused, nothing changes.
            assert (s1, s2, s3) == (3, 3, 3), (s1, s2, s3, self.mode)
            return
        # Instantiated or left in initialisation by a refused exit: the exit
        # builds the solver from the parameters set, or says why not.
        if s3 == 0:
            self.mode, self.t = "stepping", 0.0
        else:
            self.mode = "initialising"

    @rule(name=st.data(), value=values)
    def set_input(self, name, value):
        if not self.inputs:
            return
        n = name.draw(st.sampled_from(self.inputs))
        s = call(self.fmu.setReal, [self.vr[n]], [value])
        self.status_ok(s)
        if not math.isfinite(value):
            assert s == 3, f"{n} = {value} accepted"

    @rule(name=st.data(), value=values)
    def set_parameter(self, name, value):
        n = name.draw(st.sampled_from(self.params))
        self.status_ok(call(self.fmu.setReal, [self.vr[n]], [value]))

    @rule(h=steps, late=st.booleans())
    def do_step(self, h, late):
        # Late by 1 s, or by t itself where 1 s is below t's resolution
        # (after a step to t = 1e300, t + 1 is t: not late).
        self.step(self.t + (max(1.0, abs(self.t)) if late else 0.0), h, late)

    @precondition(lambda self: self.mode == "stepping" and self.inputs)
    @rule(name=st.data(), value=st.floats(-0.05, 0.05), h=st.floats(1e-3, 0.5))
    def physical_step(self, name, value, h):
        """An input within the scene's range and a step of a size a master
        would take: most sequences reach the solver this way."""
        n = name.draw(st.sampled_from(self.inputs))
        self.status_ok(call(self.fmu.setReal, [self.vr[n]], [value]))
        self.step(self.t, h, False)

    def step(self, t, h, late):
        stepping = self.mode == "stepping"
        before = self.snapshot() if stepping else None
        s = call(self.fmu.doStep, t, h)
        self.status_ok(s)
        if not stepping:
            assert s == 3, f"doStep in mode {self.mode}: {s}"
            return
        if s == 0:
            assert not late and h > 0 and math.isfinite(h)
            TALLY["steps"] += 1
            bad = [x for x in self.snapshot() if not math.isfinite(x)]
            assert bad == [], f"non-finite outputs after an accepted step: {bad[:5]}"
            if self.t + h > self.t:
                self.t += h
        else:
            # Discarded, or refused (a wrong time, a step size that is not
            # positive and finite): nothing moved, the instance steps on.
            assert s in (2, 3)
            assert self.snapshot() == before

    @precondition(lambda self: self.mode == "stepping")
    @rule()
    def save_state(self):
        state = self.fmu.getFMUstate()
        data = self.fmu.serializeFMUstate(state)
        self.fmu.freeFMUstate(state)
        self.saved = (bytes(data), self.t, self.snapshot())

    @precondition(lambda self: self.mode == "stepping" and self.saved is not None)
    @rule()
    def restore_state(self):
        data, t, outputs = self.saved
        state = self.fmu.deSerializeFMUstate(data)
        s = call(self.fmu.setFMUstate, state)
        self.fmu.freeFMUstate(state)
        self.status_ok(s)
        if s == 0:
            self.t = t
            TALLY["rollbacks"] += 1
            assert self.snapshot() == outputs
            # The state saved again is the same bytes.
            again = self.fmu.getFMUstate()
            assert bytes(self.fmu.serializeFMUstate(again)) == data
            self.fmu.freeFMUstate(again)

    @rule()
    def reset(self):
        s = call(self.fmu.reset)
        self.status_ok(s)
        if s == 0:
            self.mode, self.t, self.saved = "instantiated", 0.0, None

    @rule()
    def terminate(self):
        s = call(self.fmu.terminate)
        self.status_ok(s)
        if self.mode == "stepping":
            assert s == 0
            self.mode = "terminated"

    @invariant()
    def outputs_readable(self):
        if getattr(self, "fmu", None) is None:
            return
        s = call(self.fmu.getReal, self.outputs)
        self.status_ok(s)


def test_random_fmi_call_sequences(unpacked, capsys):
    FmiSequences.folder = str(unpacked["sliding_block"])
    run = FmiSequences.TestCase
    run.settings = settings(
        max_examples=EXAMPLES,
        stateful_step_count=STEPS,
        deadline=None,
        suppress_health_check=list(HealthCheck),
        derandomize=os.environ.get("FUZZ_RANDOM") is None,
    )
    run().runTest()
    with capsys.disabled():
        print(
            f"\nfuzz: {TALLY['sequences']} sequences, {TALLY['calls']} calls: {TALLY['steps']} steps taken "
            f"(every output finite), {TALLY['discarded']} discarded and {TALLY['errors']} errors (each logged), "
            f"{TALLY['rollbacks']} rollbacks compared (all equal)"
        )
