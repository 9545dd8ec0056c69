"""The system model of a wire-winding machine, as an FMU (pythonfmu).

The strip runs from a supply spool, round a dancer, half way round a capstan
(the contact FMU, capstan.toml) and onto a winding drum that a traverse
lays it on in layers. This model holds everything but the capstan's wrap:

- three drives (supply spool, capstan, winder), each a motor under a PI
  speed loop with acceleration feed-forward, loaded by the strip's tensions;
- a pneumatic dancer that sets the back tension T1 of the capstan's slack
  side (a first-order lag behind its set point) and whose position the
  supply spool's speed follows (a PI on the dancer position);
- the span from the capstan to the winder, an elastic strand of length
  L_span whose tension T2 follows from the material the capstan delivers
  into it (the contact FMU's speed_out) and the winder takes out of it;
- the tension controller of that span: it trims the winder's speed so that
  T2 follows its set point (PI, with the trim clamped and the integral
  frozen while clamped or far from the set point). In steady running the
  trim is the capstan's creep: the winder takes the strip up faster than
  the capstan's surface by about (1 + e2) / (1 + e1);
- the traverse, which moves one strip width per winder revolution across the
  drum and reverses at its flanges; each reversal starts a layer, and the
  winder's radius grows by one strip thickness;
- a line-speed schedule with a ramp-up, a tension step, a stop and a
  restart.

The capstan FMU is a running strip (docs/contact.md section 12): material
runs in at its supply end and out at its take-up end. What it needs from
here is the capstan's angle (its drive's rotation) and the two tensions as
forces on the strip's ends, per mm of width (-T1 / b, -T2 / b); it gives
back the material speeds at both ends: speed_in, which the dancer loop
takes up, and speed_out, which feeds the winder's span.

The tight end is force-driven, so the wrap can hold no more than
T1 exp(mu theta) there: a demand beyond it has no quasi-static state (the
strip would slide off the capstan), and the schedule stays below it.

Units: mm, s, N. Forces of the strip are totals over its width b.
"""

import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real

# Largest internal integration step (s): the speed loops' time constant is
# 0.02 s, so 1 ms keeps the explicit integration accurate.
MAX_SUBSTEP = 1.0e-3

PARAMETERS = {
    # name: (value, description)
    "b": (2.0, "strip width (mm)"),
    "t_strip": (0.05, "strip thickness (mm): the radial growth of a layer"),
    "E_strip": (20000.0, "strip's Young's modulus (MPa; capstan.toml's tape)"),
    "nu_strip": (0.3, "strip's Poisson ratio (plane strain across its width, as in the capstan)"),
    "L_span": (1000.0, "free length of the span from the capstan to the winder (mm)"),
    "v_run": (100.0, "line speed when running (mm/s)"),
    "t_ramp": (1.0, "time of a speed ramp, up or down (s)"),
    "T1_set": (20.0, "back tension set on the dancer (N)"),
    "T2_run": (30.0, "winder tension set point (N)"),
    "t_step": (8.0, "time of the tension step (s)"),
    "T2_step": (36.0, "winder tension set point after the step (N)"),
    "t_stop": (16.0, "the line starts to stop (s)"),
    "t_restart": (19.0, "the line starts again (s)"),
    "R_core": (50.0, "winder core radius (mm)"),
    "W_traverse": (8.0, "traverse width between the flanges (mm)"),
    "R_capstan": (100.0, "capstan radius (mm)"),
    "R_supply0": (150.0, "supply spool radius at the start (mm)"),
    "W_supply": (50.0, "supply spool width (mm)"),
    "tau_speed": (0.02, "speed loops' time constant (s)"),
    "tau_dancer": (0.05, "dancer's pneumatic lag (s)"),
    "K_dancer": (5.0, "supply speed correction per mm of dancer travel (1/s)"),
    "Kp_tension": (1.0, "tension controller gain (mm/s per N)"),
    "Ti_tension": (2.0, "tension controller integral time (s)"),
    "trim_max": (5.0, "largest speed trim of the winder (mm/s)"),
    "band_tension": (2.0, "the controller integrates only while |error| is under this (N)"),
}

INPUTS = {
    "speed_in": "material speed into the capstan's wrap at the slack end (mm/s; the contact FMU's strip.speed_in)",
    "speed_out": "material speed out of the capstan's wrap at the tight end (mm/s; strip.speed_out)",
}

OUTPUTS = {
    "theta_capstan": "capstan angle (rad, counter-clockwise): the contact FMU's drum.theta",
    "back_Fy": "force on the capstan strip's slack end per mm of width (N/mm, -y pulls): -T1 / b",
    "pull_Fy": "force on the capstan strip's tight end per mm of width (N/mm, -y pulls): -T2 / b",
    "T1": "back tension from the dancer (N)",
    "T2": "tension of the span to the winder (N)",
    "T2_demand": "winder tension set point (N)",
    "v_line": "line speed set point (mm/s)",
    "v_capstan": "capstan surface speed (mm/s)",
    "v_winder": "winder take-up speed (mm/s)",
    "trim": "winder speed trim of the tension controller (mm/s)",
    "R_winder": "winding radius (mm)",
    "x_traverse": "traverse position (mm)",
    "x_dancer": "dancer position from its centre (mm)",
    "R_supply": "supply spool radius (mm)",
}


class SpeedLoop:
    """A motor under a PI speed loop with acceleration feed-forward: the
    loop's closed-loop poles are both at -1/tau (critically damped)."""

    def __init__(self, inertia):
        self.inertia = inertia
        self.omega = 0.0
        self.integral = 0.0

    def advance(self, omega_set, omega_set_dot, load_torque, tau, dt):
        error = omega_set - self.omega
        wn = 1.0 / tau
        torque = self.inertia * (omega_set_dot + 2.0 * wn * error + wn * wn * self.integral) + load_torque
        self.integral += error * dt
        self.omega += (torque - load_torque) / self.inertia * dt

    def state(self):
        return [self.omega, self.integral]

    def restore(self, s):
        self.omega, self.integral = s


class WindingMachine(Fmi2Slave):
    author = "contact2d"
    description = "Wire-winding machine: supply spool, dancer, capstan drive, winder span with traverse and tension control"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        for name, (value, _) in PARAMETERS.items():
            setattr(self, name, value)
            self.register_variable(Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed))
        # Inputs: the capstan FMU's material speeds at its two ends (mm/s).
        for name in INPUTS:
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=Fmi2Causality.input))
        for name in OUTPUTS:
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=Fmi2Causality.output))
        self.layer = 0
        self.register_variable(Integer("layer", causality=Fmi2Causality.output, variability=Fmi2Variability.discrete))
        self._started = False

    # -- schedule -------------------------------------------------------
    def _speed(self, t):
        """Line speed set point and its rate at time t."""
        v, r = self.v_run, self.t_ramp
        if t < r:
            return v * t / r, v / r
        if t < self.t_stop:
            return v, 0.0
        if t < self.t_stop + r:
            return v * (1.0 - (t - self.t_stop) / r), -v / r
        if t < self.t_restart:
            return 0.0, 0.0
        if t < self.t_restart + r:
            return v * (t - self.t_restart) / r, v / r
        return v, 0.0

    def _tension_demand(self, t):
        return self.T2_step if t >= self.t_step else self.T2_run

    # -- FMI ------------------------------------------------------------
    def exit_initialization_mode(self):
        self._setup()

    def _setup(self):
        self.capstan = SpeedLoop(inertia=2.0e3)  # N mm s^2
        self.winder = SpeedLoop(inertia=5.0e2)
        self.supply = SpeedLoop(inertia=4.0e3)
        # The strip's axial stiffness (plane strain across its width, as the
        # capstan's): T = EA e.
        self.EA = self.E_strip / (1.0 - self.nu_strip**2) * self.t_strip * self.b
        self.T1 = self.T1_set
        # The winder's span starts at the back tension, as the capstan's
        # strip is laid.
        self.T2 = self.T1_set
        self.theta_capstan = 0.0
        self.R_winder = self.R_core
        self.R_supply = self.R_supply0
        self.direction = 1.0
        self.tension_integral = 0.0
        self.dancer_integral = 0.0
        self.layer = 0
        self.x_traverse = 0.0
        self.x_dancer = 0.0
        self._outputs(0.0)
        self._started = True

    def do_step(self, current_time, step_size):
        if not self._started:
            self._setup()
        n = max(1, math.ceil(step_size / MAX_SUBSTEP - 1e-9))
        dt = step_size / n
        # The capstan's material speeds, held over the step (zero-order hold).
        for k in range(n):
            self._advance(current_time + k * dt, dt, self.speed_in, self.speed_out)
        self._outputs(current_time + step_size)
        return True

    def _advance(self, t, dt, speed_in, speed_out):
        v_set, v_set_dot = self._speed(t)
        tau = self.tau_speed
        self.T1 += (self.T1_set - self.T1) * dt / self.tau_dancer
        if abs(self.T1 - self.T1_set) <= 1e-12 * abs(self.T1_set):
            self.T1 = self.T1_set
        if v_set == 0.0 and v_set_dot == 0.0:
            # Stopped: the drives' holding brakes are on, the controllers
            # wait (their integrals kept), and the strip stays where it is.
            for drive in (self.capstan, self.winder, self.supply):
                drive.omega = 0.0
            self.trim = 0.0
            return
        # Tension controller: PI on the span's tension, the trim clamped. The
        # integral only removes small offsets (the capstan's creep, the speed
        # loops' mismatch): it is frozen while the trim is clamped or the
        # error is large, so a large step does not wind it up.
        t2 = self.T2
        error = self._tension_demand(t) - t2
        trim = self.Kp_tension * (error + self.tension_integral / self.Ti_tension)
        if abs(trim) < self.trim_max and abs(error) < self.band_tension:
            self.tension_integral += error * dt
        trim = max(-self.trim_max, min(self.trim_max, trim))
        self.trim = trim
        # Drives: capstan at line speed, winder at line speed plus trim, supply
        # at line speed corrected by the dancer position.
        rc, rw, rs = self.R_capstan, self.R_winder, self.R_supply
        self.capstan.advance(v_set / rc, v_set_dot / rc, (t2 - self.T1) * rc, tau, dt)
        self.winder.advance((v_set + trim) / rw, v_set_dot / rw, t2 * rw, tau, dt)
        v_supply_set = v_set - self.K_dancer * (self.x_dancer + self.dancer_integral)
        self.supply.advance(v_supply_set / rs, v_set_dot / rs, -self.T1 * rs, tau, dt)
        v_w = self.winder.omega * rw
        v_s = self.supply.omega * rs
        self.theta_capstan += self.capstan.omega * dt
        # The winder's span: its reference length grows by what the capstan
        # delivers, speed_out / (1 + e), and shrinks by what the winder takes,
        # v_w / (1 + e), at its own strain e = T2 / EA (the strip leaves the
        # capstan at the span's tension): L de/dt = (1 + e) (v_w - speed_out).
        e = t2 / self.EA
        self.T2 += self.EA * (1.0 + e) * (v_w - speed_out) / self.L_span * dt
        # The dancer loop takes up what the supply pays out beyond what runs
        # into the capstan's wrap.
        self.x_dancer += 0.5 * (v_s - speed_in) * dt
        self.dancer_integral += self.x_dancer * dt
        self.R_supply = math.sqrt(max(self.R_supply**2 - v_s * self.b * self.t_strip / (math.pi * self.W_supply) * dt, 1.0))
        # Traverse: one strip width per winder revolution; a reversal at a
        # flange starts a new layer, one strip thickness further out.
        self.x_traverse += self.direction * self.b * self.winder.omega / (2.0 * math.pi) * dt
        if self.x_traverse >= self.W_traverse or self.x_traverse <= 0.0:
            self.x_traverse = min(max(self.x_traverse, 0.0), self.W_traverse)
            self.direction = -self.direction
            self.layer += 1
            self.R_winder += self.t_strip

    def _outputs(self, t):
        v_set, _ = self._speed(t)
        self.v_line = v_set
        self.T2_demand = self._tension_demand(t)
        self.v_capstan = self.capstan.omega * self.R_capstan
        self.v_winder = self.winder.omega * self.R_winder
        self.back_Fy = -self.T1 / self.b
        self.pull_Fy = -self.T2 / self.b

    # The state for fmi2GetFMUstate/SetFMUstate (rollback).
    def _get_fmu_state(self):
        state = super()._get_fmu_state()
        state["_internal"] = {
            "capstan": self.capstan.state(),
            "winder": self.winder.state(),
            "supply": self.supply.state(),
            "direction": self.direction,
            "tension_integral": self.tension_integral,
            "dancer_integral": self.dancer_integral,
            "EA": getattr(self, "EA", None),
            "started": self._started,
        }
        return state

    def _set_fmu_state(self, state):
        internal = state.pop("_internal")
        super()._set_fmu_state(state)
        self.capstan.restore(internal["capstan"])
        self.winder.restore(internal["winder"])
        self.supply.restore(internal["supply"])
        self.direction = internal["direction"]
        self.tension_integral = internal["tension_integral"]
        self.dancer_integral = internal["dancer_integral"]
        self.EA = internal["EA"]
        self._started = internal["started"]
