"""The FMI 3.0 FMU (`contact2d export --fmi 3`, issue 15) in fmpy: it
validates (fmpy's schema and rules, fmutool's FMI-3 checks), and stepped
along the scene's own load history with fmpy's FMU3Slave every output,
the per-node arrays included, equals the command line's summary at every
increment; FMU states restore bit for bit; directional derivatives equal
the FMI 2.0 FMU's; calls outside what it declares are refused with a
message."""

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from conftest import REPO, assert_fmu_validates, export_fmu
from test_fmu import assert_matches_summary
from test_paper_fmus import input_table

SCENES = {
    "hertz_plane_strain": (REPO / "scenes" / "hertz_plane_strain.toml", 1.0),
    "sliding_block": (REPO / "scenes" / "verification" / "sliding_block.toml", 2.0),
}


def export(contact2d, scene, out, fmi):
    return export_fmu(contact2d, scene, out, fmi=fmi)


class Slave3:
    """fmpy's FMU3Slave of an extracted FMI 3.0 FMU, read by the FMI 2.0
    names: `real("contact.Fn")`, `nodes("contact", "tn")` (one array
    variable in FMI 3.0). `vars` lists the FMI 2.0 names of every element,
    so that test_fmu.assert_matches_summary's check that every output was
    compared applies unchanged. Log messages are kept in `.messages`."""

    def __init__(self, unzipdir, name="fmu3"):
        self.md = read_model_description(str(unzipdir))
        assert self.md.fmiVersion == "3.0"
        self.by_name = {v.name: v for v in self.md.modelVariables}
        self.vars = {}
        for v in self.md.modelVariables:
            if v.dimensions:
                n = int(v.dimensions[0].start)
                for k in range(1, n + 1):
                    self.vars[f"{v.name}[{k}]"] = v
            else:
                self.vars[v.name] = v
        self.messages = []

        def log(env, status, category, message):
            self.messages.append((status, category.decode(), message.decode()))

        self.fmu = FMU3Slave(
            guid=self.md.guid,
            unzipDirectory=str(unzipdir),
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(logMessage=log)

    def vr(self, name):
        return self.by_name[name].valueReference

    def size(self, name):
        v = self.by_name[name]
        return int(v.dimensions[0].start) if v.dimensions else 1

    def init(self):
        self.fmu.enterInitializationMode(startTime=0.0)
        self.fmu.exitInitializationMode()
        return self

    def real(self, name):
        return self.fmu.getFloat64([self.vr(name)])[0]

    def int(self, name):
        return self.fmu.getInt32([self.vr(name)])[0]

    def nodes(self, pair, what):
        name = f"{pair}.{what}"
        get = self.fmu.getInt32 if what == "state" else self.fmu.getFloat64
        return get([self.vr(name)], nValues=self.size(name))

    def outputs(self):
        """Every output, arrays as lists, by FMI 3.0 name."""
        out = {}
        for name, v in self.by_name.items():
            if v.causality != "output":
                continue
            get = self.fmu.getInt32 if v.type == "Int32" else self.fmu.getFloat64
            out[name] = get([v.valueReference], nValues=self.size(name))
        return out

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        self.fmu.freeLibrary()


@pytest.mark.parametrize("name", sorted(SCENES))
def test_fmi3_fmu_validates_and_steps_as_the_cli(name, contact2d, cli_summary, tmp_path):
    scene, length_scale = SCENES[name]
    fmu = export(contact2d, scene, tmp_path / f"{name}.fmu", 3)
    assert_fmu_validates(fmu, fmi=3)
    steps = cli_summary(scene)["steps"]
    table = input_table(contact2d, scene, tmp_path)
    slave = Slave3(extract(str(fmu), str(tmp_path / "unpacked")), name)
    try:
        slave.init()
        # The independent variable, and a pair's per-node outputs as arrays.
        assert slave.by_name["time"].causality == "independent"
        pair = next(iter(steps[0]["pairs"]))
        assert slave.size(f"{pair}.tn") == len(steps[0]["pairs"][pair]["nodes"]["tn"]) > 1
        names = list(table[0][1])
        vrs = [slave.vr(n) for n in names]
        for (t0, _), (t1, then), step in zip(table, table[1:], steps):
            slave.fmu.setFloat64(vrs, [then[n] for n in names])
            event, terminate, early, reached = slave.fmu.doStep(t0, t1 - t0)
            assert (event, terminate, early, reached) == (False, False, False, t1)
            assert slave.real("time") == t1
            forces = [abs(v) for d in step["drivers"].values() for v in d.values()]
            forces += [abs(p[c]) for p in step["pairs"].values() for c in ("Fx", "Fy", "Fn", "Ft")]
            assert_matches_summary(slave, step, force_scale=max(forces), length_scale=length_scale)
    finally:
        slave.free()
    assert not [m for m in slave.messages if m[0] >= 3], slave.messages


def test_fmi3_states_derivatives_and_refusals(contact2d, tmp_path):
    """The sliding block, pressed and dragged into partial slip: a saved
    state, serialized and read back, continues bit for bit; the directional
    derivatives equal the FMI 2.0 FMU's (same library, same state); wrong
    sizes, `time` as an input, and event mode are refused by name."""
    from conftest import Slave

    scene = REPO / "scenes" / "verification" / "sliding_block.toml"
    fmu3 = export(contact2d, scene, tmp_path / "block3.fmu", 3)
    fmu2 = export(contact2d, scene, tmp_path / "block2.fmu", 2)
    table = input_table(contact2d, scene, tmp_path)
    three = Slave3(extract(str(fmu3), str(tmp_path / "u3")), "three").init()
    two = Slave(extract(str(fmu2), str(tmp_path / "u2")), "two").init()
    try:
        names = list(table[0][1])
        steps = list(zip(table, table[1:]))[:12]
        for (t0, _), (t1, then) in steps[:6]:
            three.fmu.setFloat64([three.vr(n) for n in names], [then[n] for n in names])
            three.fmu.doStep(t0, t1 - t0)
            two.fmu.setReal([two.vr(n) for n in names], [then[n] for n in names])
            two.fmu.doStep(t0, t1 - t0)
        saved = three.fmu.getFMUState()
        blob = three.fmu.serializeFMUState(saved)
        three.fmu.freeFMUState(saved)

        def run_on():
            seen = []
            for (t0, _), (t1, then) in steps[6:]:
                three.fmu.setFloat64([three.vr(n) for n in names], [then[n] for n in names])
                three.fmu.doStep(t0, t1 - t0)
                seen.append(three.outputs())
            return seen

        # Derivatives at step 6 (the drag's transition: stick and slip).
        states = three.nodes("base", "state")
        assert 1 in states and 2 in states, states
        unknowns = ["top.Rx", "top.Ry", "base.Fn", "base.Ft"]
        knowns = ["top.uy", "plane.uy"]
        d3 = three.fmu.getDirectionalDerivative(
            [three.vr(n) for n in unknowns], [three.vr(n) for n in knowns], [1.0, 0.5]
        )
        d2 = two.fmu.getDirectionalDerivative(
            [two.vr(n) for n in unknowns], [two.vr(n) for n in knowns], [1.0, 0.5]
        )
        assert d3 == d2
        first = run_on()
        state = three.fmu.deserializeFMUState(blob)
        three.fmu.setFMUState(state)
        three.fmu.freeFMUState(state)
        assert run_on() == first

        # Refusals, each with a message that names what is wrong.
        def refused(call, *args, says):
            before = len(three.messages)
            with pytest.raises(Exception):
                call(*args)
            text = " ".join(m[2] for m in three.messages[before:])
            assert says in text, three.messages[before:]

        refused(three.fmu.getFloat64, [three.vr("base.tn")], 3, says="nValues = 3")
        refused(three.fmu.setFloat64, [0], [1.0], says="`time`")
        refused(three.fmu.setFloat64, [three.vr("base.Fn")], [1.0], says="base.Fn")
        refused(three.fmu.getInt32, [three.vr("base.Fn")], says="not Integer")
        refused(three.fmu.getBoolean, [1], says="no variables of this type")
        refused(three.fmu.enterEventMode, says="no event mode")
    finally:
        three.free()
        two.free()

    # Event mode asked for at instantiation: NULL, and the reason logged.
    seen = []
    md = read_model_description(str(fmu3))
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=str(tmp_path / "u3"),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="events",
    )
    with pytest.raises(Exception, match="Failed to instantiate"):
        fmu.instantiate(eventModeUsed=True, logMessage=lambda env, s, c, m: seen.append(m.decode()))
    fmu.freeLibrary()
    assert any("eventModeUsed" in m for m in seen), seen
