# yade-flex demo: a ball dropped on a steel ring standing on a wire (GPL-2.0-or-later).
#
#   yade-double -n -x scripts/demo_cylinders.py --out DIR [--duration S] [--drop-height H]
#
# Scene: yadeflex.scenes.wire_and_ring (steel wire clamped at both ends, steel ring standing on
# it at mid-span, steel ball dropped on the ring), no damping, energy tracked. Everything starts
# at rest, so O.energy.total() must stay at 0; its drift is the energy-balance residual.
#
# Writes into DIR: timeseries.csv, params.json, summary.json, demo.png.
# Exit status: 0 completed; 2 NaN/Inf in the state (the body is named); 3 energy balance
# diverged (|residual| > --max-residual x the nominal impact energy); 1 any other error.
# Files are written in every case (up to the stop).
import argparse
import builtins
import csv
import json
import math
import os
import platform
import subprocess
import sys
import time
import traceback

import numpy as np

from yade import O
from yade.wrapper import PyRunner
import yade.config

import yadeflex as yf
from yadeflex import scenes

GRAVITY = 9.81  # m/s2, as in yadeflex.scene.engines()
KNOWN_ENERGIES = ["kinetic", "gravWork", "flexBondElastic", "flexContactElastic", "flexFriction",
                  "flexBondPlastic", "flexRupture", "nonviscDamp"]
# YADE's -x runner sets sys.argv[0] to this script's path (__file__ is YADE's own launcher)
REPO = os.path.dirname(os.path.dirname(os.path.abspath(sys.argv[0])))


def parse_args(argv):
    p = argparse.ArgumentParser(prog="yade-double -n -x scripts/demo_cylinders.py",
                                description="yade-flex demo: a ball dropped on a steel ring standing on a clamped wire.")
    p.add_argument("--out", required=True, help="output directory (created)")
    p.add_argument("--duration", type=float, default=None,
                   help="simulated time [s] (default: nominal free-fall time of the ball to the ring + 0.5 s)")
    p.add_argument("--drop-height", type=float, default=None,
                   help="drop height of the ball above the ring [m] (default: wire_and_ring's default)")
    p.add_argument("--sample-every", type=int, default=100, help="time-series row every N steps (default 100)")
    p.add_argument("--peak-every", type=int, default=5,
                   help="force peaks and first impact tracked every N steps (default 5)")
    p.add_argument("--progress-seconds", type=float, default=3.0, help="wall seconds between progress lines")
    p.add_argument("--max-residual", type=float, default=1.0,
                   help="stop when |energy residual| exceeds this fraction of the nominal impact energy "
                        "(default 1.0 = 100%%: the run is no longer physical; inf disables)")
    p.add_argument("--timestep-safety", type=float, default=None,
                   help="override FlexTimeStepper.safety (default: the engine list's default)")
    a = p.parse_args(argv)
    if a.duration is not None and not (a.duration > 0 and math.isfinite(a.duration)):
        p.error(f"--duration must be a positive number of seconds, got {a.duration}")
    if a.drop_height is not None and not (a.drop_height > 0 and math.isfinite(a.drop_height)):
        p.error(f"--drop-height must be a positive number of metres, got {a.drop_height}")
    for name in ("sample_every", "peak_every"):
        if getattr(a, name) < 1:
            p.error(f"--{name.replace('_', '-')} must be >= 1")
    if a.sample_every % a.peak_every:
        p.error("--sample-every must be a multiple of --peak-every")
    if not a.max_residual > 0:
        p.error("--max-residual must be > 0")
    if a.timestep_safety is not None and not (0 < a.timestep_safety <= 1):
        p.error("--timestep-safety must be in (0, 1]")
    return a


def git_state():
    try:
        rev = subprocess.run(["git", "-C", REPO, "rev-parse", "HEAD"], capture_output=True, text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", REPO, "status", "--porcelain", "--untracked-files=no"], capture_output=True, text=True,
                               timeout=10).stdout.strip() != ""
        return dict(commit=rev or None, dirty=dirty)
    except Exception:
        return dict(commit=None, dirty=None)


def seg_seg_dist(P0, P1, Q0, Q1):
    """Distances between segments P0-P1 and Q0-Q1 (arrays broadcasting to (..., 3))."""
    d1, d2, r = P1 - P0, Q1 - Q0, P0 - Q0
    a = np.einsum("...i,...i", d1, d1)
    e = np.einsum("...i,...i", d2, d2)
    b = np.einsum("...i,...i", d1, d2)
    c = np.einsum("...i,...i", d1, r)
    f = np.einsum("...i,...i", d2, r)
    a, e, b, c, f = np.broadcast_arrays(a, e, b, c, f)
    denom = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(denom > 1e-14 * a * e, np.clip((b * f - c * e) / denom, 0, 1), 0.0)
        t = (b * s + f) / e
        s = np.where(t < 0, np.clip(-c / a, 0, 1), np.where(t > 1, np.clip((b - c) / a, 0, 1), s))
        t = np.clip(t, 0, 1)
    diff = (P0 + d1 * s[..., None]) - (Q0 + d2 * t[..., None])
    return np.sqrt(np.einsum("...i,...i", diff, diff))


def point_seg_dist(X, P0, P1):
    d = P1 - P0
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.clip(np.einsum("...i,...i", X - P0, d) / np.einsum("...i,...i", d, d), 0, 1)
    diff = X - (P0 + d * s[..., None])
    return np.sqrt(np.einsum("...i,...i", diff, diff))


def inside_polygon(pts2, poly2):
    """Even-odd rule: which 2D points pts2 (n, 2) are inside the closed polygon poly2 (m, 2)."""
    x, y = pts2[:, 0][:, None], pts2[:, 1][:, None]
    xa, ya = poly2[:, 0][None, :], poly2[:, 1][None, :]
    xb, yb = np.roll(poly2[:, 0], -1)[None, :], np.roll(poly2[:, 1], -1)[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = ((ya > y) != (yb > y)) & (x < (xb - xa) * (y - ya) / (yb - ya) + xa)
    return np.count_nonzero(cross, axis=1) % 2 == 1


class Demo:
    def __init__(self, args):
        self.args = args
        kw = {} if args.drop_height is None else dict(drop_height=args.drop_height)
        self.scene = scenes.wire_and_ring(**kw)
        O.trackEnergy = True
        s = self.scene
        self.p = s["params"]
        self.ball = s["ball"]
        self.wn, self.wc, self.rn, self.rc = s["wire_nodes"], s["wire_cylinders"], s["ring_nodes"], s["ring_cylinders"]
        self.mid = self.wn[len(self.wn) // 2]
        self.R_ball = O.bodies[self.ball].shape.radius
        self.r_wire, self.r_ring = self.p["wire_radius"], self.p["ring_bar_radius"]
        self.wc_shapes = [O.bodies[i].shape for i in self.wc]
        self.rc_shapes = [O.bodies[i].shape for i in self.rc]
        # segment end indices into the node arrays
        self.wseg = np.array([[self.wn.index(O.bodies[i].shape.node1), self.wn.index(O.bodies[i].shape.node2)] for i in self.wc])
        self.rseg = np.array([[self.rn.index(O.bodies[i].shape.node1), self.rn.index(O.bodies[i].shape.node2)] for i in self.rc])
        self.node_ids = list(self.wn) + list(self.rn) + [self.ball]
        self.node_states = [O.bodies[i].state for i in self.node_ids]
        self.ball_state = O.bodies[self.ball].state
        self.m_ball = self.ball_state.mass
        self.m_wire = sum(O.bodies[i].state.mass for i in self.wn)  # clamped end nodes carry their share too
        self.m_ring = sum(O.bodies[i].state.mass for i in self.rn)
        self.z_mid0 = O.bodies[self.mid].state.pos[2]
        self.z_ball0 = self.ball_state.pos[2]
        ring_top0 = max(O.bodies[i].state.pos[2] for i in self.rn) + self.r_ring
        self.gap0 = (self.z_ball0 - self.R_ball) - ring_top0
        # nominal impact energy: the ball's potential energy released before it first touches the ring
        self.E_ref = self.m_ball * GRAVITY * self.gap0
        self.t_fall = math.sqrt(2 * self.gap0 / GRAVITY)
        self.duration = args.duration if args.duration is not None else round(self.t_fall + 0.5, 3)
        dts = [e for e in O.engines if getattr(e, "label", "") == "flexDt"]
        self.flexDt = dts[0] if dts else None
        if args.timestep_safety is not None:
            if self.flexDt is None:
                raise RuntimeError("no engine labelled 'flexDt' (FlexTimeStepper) to apply --timestep-safety to")
            self.flexDt.safety = args.timestep_safety
        # run state
        self.rows = []
        self.energy_keys = list(KNOWN_ENERGIES)
        self.E0 = None
        self.peak = dict(ball_force=(0.0, 0.0), wire_axial=(0.0, 0.0), ring_axial=(0.0, 0.0))  # (value, time)
        self.iv = dict(ball_force=0.0, wire_axial=0.0, ring_axial=0.0)  # peaks since the last row
        self.impact = None  # dict(time, ke, vz, z)
        self.max_defl = (0.0, 0.0)
        self.max_res = (0.0, 0.0)
        self.overlap = dict(ball_ring=(-math.inf, 0.0), ball_wire=(-math.inf, 0.0), ring_wire=(-math.inf, 0.0))
        self.crossings = []  # pass-through events found by the topological check
        self.prev_inside = None
        self.dt_min, self.dt_max = math.inf, 0.0
        self.dt_first = None  # O.dt is YADE's default until FlexTimeStepper's first step
        self.warned_res = False
        self.stop = None  # (exit code, message)
        self.stop_short = None  # one line for the figure
        self.done = False
        self.error = None

    # ---- naming ------------------------------------------------------------------------
    def name(self, bid):
        if bid == self.ball:
            return f"ball #{bid}"
        if bid in self.wn:
            k = self.wn.index(bid)
            return f"wire node #{bid} (index {k} of {len(self.wn)}{', mid-span' if bid == self.mid else ''})"
        if bid in self.rn:
            return f"ring node #{bid} (index {self.rn.index(bid)} of {len(self.rn)})"
        if bid in self.wc:
            return f"wire cylinder #{bid} (segment {self.wc.index(bid)})"
        if bid in self.rc:
            return f"ring cylinder #{bid} (segment {self.rc.index(bid)})"
        return f"body #{bid}"

    def nonfinite_bodies(self):
        bad = []
        for i in self.node_ids:
            st = O.bodies[i].state
            what = [w for w, v in (("position", st.pos), ("velocity", st.vel), ("angular velocity", st.angVel))
                    if not all(math.isfinite(x) for x in v)]
            if what:
                bad.append(f"{self.name(i)}: non-finite {', '.join(what)} (pos={tuple(st.pos)}, vel={tuple(st.vel)})")
        for i, sh in zip(self.wc + self.rc, self.wc_shapes + self.rc_shapes):
            if not math.isfinite(sh.axialForce):
                bad.append(f"{self.name(i)}: non-finite axial force {sh.axialForce}")
        if not math.isfinite(O.bodies[self.ball].state.pos.norm()) or not math.isfinite(O.forces.f(self.ball).norm()):
            bad.append(f"{self.name(self.ball)}: non-finite force {tuple(O.forces.f(self.ball))}")
        return bad

    def abort(self, code, msg, short=None):
        if self.stop is None:
            self.stop = (code, msg)
            self.stop_short = short or msg.splitlines()[0][:120]
        O.pause()

    # ---- engine callback -------------------------------------------------------------------
    def tick(self):
        try:
            self._tick()
        except Exception:
            self.error = traceback.format_exc()
            O.pause()

    def _tick(self):
        t = O.time
        dt = O.dt
        if self.dt_first is None:
            self.dt_first = dt
        self.dt_min, self.dt_max = min(self.dt_min, dt), max(self.dt_max, dt)
        fb = O.forces.f(self.ball).norm()
        wa = max(abs(sh.axialForce) for sh in self.wc_shapes)
        ra = max(abs(sh.axialForce) for sh in self.rc_shapes)
        if not (math.isfinite(fb) and math.isfinite(wa) and math.isfinite(ra) and math.isfinite(O.energy.total())):
            self.abort_nan()
            return
        for key, v in (("ball_force", fb), ("wire_axial", wa), ("ring_axial", ra)):
            if v > self.peak[key][0]:
                self.peak[key] = (v, t)
            self.iv[key] = max(self.iv[key], v)
        if self.impact is None and fb > 0 and yf.contacts_on(self.ball):
            v = self.ball_state.vel
            self.impact = dict(time=t, kinetic_energy=0.5 * self.m_ball * v.squaredNorm(), vz=v[2], z=self.ball_state.pos[2],
                               bodies=[self.name(i.id1 if i.id2 == self.ball else i.id2) for i in yf.contacts_on(self.ball)])
            print(f"impact: ball touches {', '.join(self.impact['bodies'])} at t={t:.4f} s, vz={v[2]:.3f} m/s, "
                  f"kinetic energy {self.impact['kinetic_energy']:.2f} J (nominal {self.E_ref:.2f} J)", flush=True)
        if O.iter % self.args.sample_every == 0 or self.E0 is None:
            self.record()
        if self.stop is None and t >= self.duration:
            self.done = True
            self.record(force=True)
            O.pause()
            return
        now = time.time()
        if now - self.last_progress >= self.args.progress_seconds:
            self.progress(now)

    def abort_nan(self):
        bad = self.nonfinite_bodies()
        where = "; ".join(bad[:5]) + (f"; ... ({len(bad)} in all)" if len(bad) > 5 else "") if bad else \
            "a force or O.energy.total() became non-finite (no body state is non-finite yet)"
        self.abort(2, f"NaN/Inf at t={O.time:.6g} s (iteration {O.iter}): {where}",
                   f"NaN/Inf: {bad[0].split(':')[0] if bad else 'forces or energy'}{f' and {len(bad) - 1} more' if len(bad) > 1 else ''}")

    def record(self, force=False):
        if self.rows and self.rows[-1]["iteration"] == O.iter:
            return
        t = O.time
        # non-finite velocities show up in O.energy['kinetic'], checked by tick() every few steps
        npos = np.array([tuple(st.pos) for st in self.node_states])
        if not (np.all(np.isfinite(npos)) and math.isfinite(O.energy.total())):
            self.abort_nan()
            return
        nw, nr = len(self.wn), len(self.rn)
        W, Rg, B = npos[:nw], npos[nw:nw + nr], npos[-1]
        bs = self.ball_state
        e = {k: O.energy[k] for k in O.energy.keys()}
        for k in e:
            if k not in self.energy_keys:
                self.energy_keys.append(k)
        total = O.energy.total()
        if self.E0 is None:
            self.E0 = total  # 0 when everything starts at rest
        res = total - self.E0
        rel = res / self.E_ref
        contacts = ball_contacts = 0
        for i in O.interactions:
            if not i.isReal:
                continue
            g = i.geom
            if hasattr(g, "active") and not g.active:
                continue
            contacts += 1
            if self.ball in (i.id1, i.id2):
                ball_contacts += 1
        mid_z = W[self.wn.index(self.mid), 2]
        defl = self.z_mid0 - mid_z
        # geometry checks, independent of the contact detection: overlaps of the bodies' surfaces
        wP0, wP1 = W[self.wseg[:, 0]], W[self.wseg[:, 1]]
        rP0, rP1 = Rg[self.rseg[:, 0]], Rg[self.rseg[:, 1]]
        ov_bw = float(np.max(self.R_ball + self.r_wire - point_seg_dist(B[None, :], wP0, wP1)))
        ov_br = float(np.max(self.R_ball + self.r_ring - point_seg_dist(B[None, :], rP0, rP1)))
        ov_rw = float(np.max(self.r_ring + self.r_wire - seg_seg_dist(rP0[:, None, :], rP1[:, None, :], wP0[None, :, :], wP1[None, :, :])))
        for key, v in (("ball_ring", ov_br), ("ball_wire", ov_bw), ("ring_wire", ov_rw)):
            if v > self.overlap[key][0]:
                self.overlap[key] = (v, t)
        self.check_crossings(W, Rg, B, t)
        row = dict(iteration=O.iter, time=t, dt=O.dt if O.iter > 0 else math.nan,
                   ball_z=bs.pos[2], ball_vz=bs.vel[2], ball_y=bs.pos[1],
                   ball_force=O.forces.f(self.ball).norm(), ball_force_peak=self.iv["ball_force"],
                   wire_mid_z=mid_z, wire_mid_deflection=defl,
                   wire_axial=max(abs(sh.axialForce) for sh in self.wc_shapes), wire_axial_peak=self.iv["wire_axial"],
                   ring_axial=max(abs(sh.axialForce) for sh in self.rc_shapes), ring_axial_peak=self.iv["ring_axial"],
                   ring_centroid_z=float(np.mean(Rg[:, 2])),
                   contacts=contacts, ball_contacts=ball_contacts,
                   energies=e, total=total, residual=res, residual_rel=rel,
                   overlap_ball_ring=ov_br, overlap_ball_wire=ov_bw, overlap_ring_wire=ov_rw)
        self.rows.append(row)
        for k in self.iv:
            self.iv[k] = 0.0
        if defl > self.max_defl[0]:
            self.max_defl = (defl, t)
        if abs(res) > abs(self.max_res[0]):
            self.max_res = (res, t)
        if abs(rel) > 0.02 and not self.warned_res:
            self.warned_res = True
            print(f"WARNING: energy balance residual {100 * rel:+.2f}% of the nominal impact energy at t={t:.4f} s "
                  f"({res:+.4g} J); the run is not conserving energy", flush=True)
        if abs(rel) > self.args.max_residual:
            terms = ", ".join(f"{k}={v:.4g}" for k, v in e.items())
            self.abort(3, f"energy balance diverged at t={t:.6g} s (iteration {O.iter}): residual {res:+.4g} J = "
                          f"{100 * rel:+.1f}% of the nominal impact energy {self.E_ref:.4g} J (limit {100 * self.args.max_residual:g}%); "
                          f"terms [J]: {terms}; dt={O.dt:.3e} s. This is a numerical instability, not physics.",
                       f"energy balance diverged: residual {100 * rel:+.0f}% of the impact energy (numerical instability)")

    def check_crossings(self, W, Rg, B, t):
        """Pass-through check: a wire node or the ball centre moving between the inside and the
        outside of the ring's outline while staying in the ring's slab (within contact reach
        of the ring plane) went through the ring bar."""
        c = Rg.mean(axis=0)
        u, s, vt = np.linalg.svd(Rg - c)
        n, e1, e2 = vt[2], vt[0], vt[1]
        pts = np.vstack([W, B[None, :]])
        reach = np.concatenate([np.full(len(W), self.r_wire + self.r_ring), [self.R_ball + self.r_ring]])
        slab = np.abs((pts - c) @ n) < reach
        poly = np.column_stack([(Rg - c) @ e1, (Rg - c) @ e2])
        inside = inside_polygon(np.column_stack([(pts - c) @ e1, (pts - c) @ e2]), poly)
        if self.prev_inside is not None:
            pin, pslab = self.prev_inside
            for k in np.nonzero((inside != pin) & slab & pslab)[0]:
                who = self.name(self.ball) if k == len(W) else self.name(self.wn[k])
                ev = dict(time=t, body=who, direction="into the ring outline" if inside[k] else "out of the ring outline")
                self.crossings.append(ev)
                if len(self.crossings) <= 5:
                    print(f"WARNING: {who} crossed the ring bar ({ev['direction']}) at t={t:.5f} s: "
                          f"pass-through (contact missed or too soft)", flush=True)
        self.prev_inside = (inside, slab)

    def progress(self, now):
        el = now - self.t_start
        frac = min(O.time / self.duration, 1.0)
        rate = (O.iter - self.iter_start) / el if el > 0 else 0.0
        eta = el * (1 - frac) / frac if frac > 0 else math.inf
        res = self.rows[-1]["residual_rel"] if self.rows else 0.0
        print(f"[{100 * frac:5.1f}%] t={O.time:.4f}/{self.duration:g} s  step {O.iter}  dt={O.dt:.2e} s  {rate:,.0f} steps/s  "
              f"ETA {eta:.0f} s  contacts {self.rows[-1]['contacts'] if self.rows else 0}  energy residual {100 * res:+.3f}%", flush=True)
        self.last_progress = now

    # ---- run -------------------------------------------------------------------------------
    def run(self):
        builtins._yadeflex_demo_tick = self.tick
        O.engines = O.engines + [PyRunner(iterPeriod=self.args.peak_every, command="_yadeflex_demo_tick()", label="demoTick")]
        print(f"wire_and_ring: {len(O.bodies)} bodies; ball {self.m_ball:.3f} kg, ring {self.m_ring:.3f} kg, wire {self.m_wire:.4f} kg; "
              f"ball {self.gap0:.4f} m above the ring (nominal impact at t={self.t_fall:.3f} s, impact energy {self.E_ref:.3f} J); "
              f"simulating {self.duration:g} s", flush=True)
        self.t_start = self.last_progress = time.time()
        self.iter_start = O.iter
        self.record()
        O.run(2 ** 62, True)
        self.wall = time.time() - self.t_start
        if self.error:
            self.stop = (1, "error in the recorder:\n" + self.error)
        elif not self.done and self.stop is None:
            self.stop = (1, f"the simulation stopped unexpectedly at t={O.time:.6g} s (iteration {O.iter}); see YADE's messages above")
        self.progress(time.time())

    # ---- outputs -----------------------------------------------------------------------------
    def columns(self):
        cols = [("iteration", "iteration", "-"), ("time", "time", "s"), ("dt", "dt", "s"),
                ("ball_z", "ball_z", "m"), ("ball_vz", "ball_vz", "m/s"), ("ball_y", "ball_y", "m"),
                ("ball_force", "ball_contact_force", "N"), ("ball_force_peak", "ball_contact_force_peak_since_prev_row", "N"),
                ("wire_mid_z", "wire_midspan_z", "m"), ("wire_mid_deflection", "wire_midspan_deflection_down", "m"),
                ("wire_axial", "wire_max_abs_axial_force", "N"), ("wire_axial_peak", "wire_max_abs_axial_force_peak_since_prev_row", "N"),
                ("ring_axial", "ring_max_abs_axial_force", "N"), ("ring_axial_peak", "ring_max_abs_axial_force_peak_since_prev_row", "N"),
                ("ring_centroid_z", "ring_centroid_z", "m"),
                ("contacts", "active_contacts", "-"), ("ball_contacts", "ball_active_contacts", "-")]
        cols += [("E:" + k, "E_" + k, "J") for k in self.energy_keys]
        cols += [("total", "E_total", "J"), ("residual", "energy_residual", "J"), ("residual_rel", "energy_residual_rel_nominal_impact", "-"),
                 ("overlap_ball_ring", "overlap_ball_ring", "m"), ("overlap_ball_wire", "overlap_ball_wire", "m"),
                 ("overlap_ring_wire", "overlap_ring_wire", "m")]
        return cols

    def write(self, out, status_code, status_msg):
        os.makedirs(out, exist_ok=True)
        cols = self.columns()
        with open(os.path.join(out, "timeseries.csv"), "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow([f"{name}[{unit}]" for _, name, unit in cols])
            for r in self.rows:
                vals = []
                for key, _, _ in cols:
                    v = r["energies"].get(key[2:], 0.0) if key.startswith("E:") else r[key]
                    vals.append(v if isinstance(v, int) else f"{v:.10g}")
                w.writerow(vals)
        a = self.args
        params = dict(scene="yadeflex.scenes.wire_and_ring", scene_params=self.p,
                      derived=dict(ball_mass_kg=self.m_ball, ring_mass_kg=self.m_ring, wire_mass_kg=self.m_wire,
                                   ball_radius_m=self.R_ball, initial_gap_ball_to_ring_m=self.gap0,
                                   nominal_impact_energy_J=self.E_ref, nominal_impact_time_s=self.t_fall,
                                   nominal_impact_speed_m_s=math.sqrt(2 * GRAVITY * self.gap0), gravity_m_s2=GRAVITY,
                                   midspan_node=self.mid, bodies=len(O.bodies)),
                      run=dict(duration_s=self.duration, duration_default=a.duration is None, sample_every_steps=a.sample_every,
                               peak_every_steps=a.peak_every, max_residual=a.max_residual,
                               timestep_safety=self.flexDt.safety if self.flexDt else None,
                               timestep_safety_overridden=a.timestep_safety is not None,
                               timestep_interval=self.flexDt.interval if self.flexDt else None,
                               threads=O.numThreads, track_energy=True, argv=sys.argv),
                      environment=dict(yade=yade.config.version, python=platform.python_version(), host=platform.node(),
                                       yadeflex_module=os.path.dirname(yf.__file__), repo=REPO, git=git_state()))
        with open(os.path.join(out, "params.json"), "w") as fh:
            json.dump(params, fh, indent=2, default=float)
        steps = O.iter - self.iter_start
        imp = self.impact
        res_J, res_t = self.max_res
        summary = dict(
            status="completed" if status_code == 0 else "stopped",
            exit_code=status_code,
            message=status_msg,
            simulated_time_s=O.time, requested_duration_s=self.duration,
            steps=steps, dt_first_s=self.dt_first, dt_min_s=self.dt_min if steps else None,
            dt_max_s=self.dt_max if steps else None, dt_last_s=O.dt,
            wall_time_s=self.wall, time_per_step_us=1e6 * self.wall / steps if steps else None,
            steps_per_s=steps / self.wall if self.wall > 0 else None,
            impact=(dict(time_s=imp["time"], kinetic_energy_J=imp["kinetic_energy"], vz_m_s=imp["vz"], ball_z_m=imp["z"],
                         touched=imp["bodies"]) if imp else None),
            peak_ball_contact_force_N=self.peak["ball_force"][0], peak_ball_contact_force_time_s=self.peak["ball_force"][1],
            peak_wire_axial_force_N=self.peak["wire_axial"][0], peak_wire_axial_force_time_s=self.peak["wire_axial"][1],
            peak_ring_axial_force_N=self.peak["ring_axial"][0], peak_ring_axial_force_time_s=self.peak["ring_axial"][1],
            peaks_sampled_every_steps=a.peak_every,
            max_midspan_deflection_m=self.max_defl[0], max_midspan_deflection_time_s=self.max_defl[1],
            min_ball_z_m=min((r["ball_z"] for r in self.rows), default=None),
            energy_reference=("nominal impact energy m_ball*g*h: the ball's potential energy released before it first touches "
                              "the ring (h = initial gap between the ball's bottom and the ring's top)"),
            energy_reference_J=self.E_ref,
            max_abs_energy_residual_J=abs(res_J), max_energy_residual_signed_J=res_J, max_energy_residual_time_s=res_t,
            max_energy_residual_rel_reference=abs(res_J) / self.E_ref,
            max_energy_residual_rel_measured_impact_ke=(abs(res_J) / imp["kinetic_energy"] if imp and imp["kinetic_energy"] > 0 else None),
            final_energy_residual_J=self.rows[-1]["residual"] if self.rows else None,
            final_energies_J=dict(self.rows[-1]["energies"], total=self.rows[-1]["total"]) if self.rows else None,
            max_overlap_m={k: v[0] for k, v in self.overlap.items()},
            max_overlap_time_s={k: v[1] for k, v in self.overlap.items()},
            overlap_note=("largest geometric overlap of the surfaces (r1 + r2 - axis distance) at the recorded rows; "
                          f"wire radius {self.r_wire} m, ring bar radius {self.r_ring} m"),
            pass_through_events=self.crossings[:50], pass_through_count=len(self.crossings),
            rows=len(self.rows),
        )
        with open(os.path.join(out, "summary.json"), "w") as fh:
            json.dump(summary, fh, indent=2, default=float)
        self.plot(os.path.join(out, "demo.png"), status_code, status_msg)
        return summary

    def plot(self, path, status_code, status_msg):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        R = self.rows
        t = np.array([r["time"] for r in R])
        col = lambda k: np.array([r[k] for r in R])
        fig, ax = plt.subplots(2, 2, figsize=(13, 9.5), constrained_layout=True)
        # (a) heights
        a = ax[0, 0]
        a.plot(t, col("ball_z"), color="C0", label="ball centre z")
        a.plot(t, col("ring_centroid_z"), color="C2", label="ring centroid z")
        a.set_xlabel("time [s]")
        a.set_ylabel("height [m]")
        b = a.twinx()
        b.plot(t, 1e3 * col("wire_mid_z"), color="C3", label="wire mid-span z")
        b.set_ylabel("wire mid-span z [mm]", color="C3")
        b.tick_params(axis="y", colors="C3")
        h1, l1 = a.get_legend_handles_labels()
        h2, l2 = b.get_legend_handles_labels()
        a.legend(h1 + h2, l1 + l2, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=8)
        a.set_title("ball height and wire mid-span")
        # (b) ball contact force
        a = ax[0, 1]
        a.plot(t, col("ball_force_peak"), color="C1", lw=0.8, alpha=0.6, label=f"peak between rows (every {self.args.peak_every} steps)")
        a.plot(t, col("ball_force"), color="C0", lw=1.0, label="at the row")
        a.set_xlabel("time [s]")
        a.set_ylabel("|contact force on ball| [N]")
        a.legend(loc="upper right", fontsize=8)
        a.set_title("ball contact force")
        # (c) axial forces
        a = ax[1, 0]
        a.plot(t, 1e-3 * col("wire_axial_peak"), color="C0", lw=0.8, alpha=0.5)
        a.plot(t, 1e-3 * col("wire_axial"), color="C0", label="wire, max |N|")
        a.plot(t, 1e-3 * col("ring_axial_peak"), color="C3", lw=0.8, alpha=0.5)
        a.plot(t, 1e-3 * col("ring_axial"), color="C3", label="ring, max |N|")
        a.set_xlabel("time [s]")
        a.set_ylabel("axial force [kN]")
        a.legend(loc="upper right", fontsize=8, title="light: peak between rows", title_fontsize=7)
        a.set_title("bond axial forces")
        # (d) energies
        a = ax[1, 1]
        for k, key in enumerate(self.energy_keys):
            v = np.array([r["energies"].get(key, 0.0) for r in R])
            if np.any(v != 0):
                a.plot(t, v, lw=1.0, label=key, color=f"C{k % 10}")
        a.plot(t, col("total"), color="k", lw=2.0, label="total (should stay 0)")
        a.set_xlabel("time [s]")
        a.set_ylabel("energy [J]")
        b = a.twinx()
        b.plot(t, 100 * col("residual_rel"), color="0.5", lw=0.8, ls="--", label="residual [% of reference]")
        b.set_ylabel(f"residual [% of {self.E_ref:.1f} J]", color="0.4")
        b.tick_params(axis="y", colors="0.4")
        h1, l1 = a.get_legend_handles_labels()
        h2, l2 = b.get_legend_handles_labels()
        a.legend(h1 + h2, l1 + l2, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=4, fontsize=7)
        worst = max((abs(r["residual_rel"]) for r in R), default=0.0)
        a.set_title(f"energy terms (max |residual| {100 * worst:.2f}% of {self.E_ref:.1f} J)")
        if self.impact:
            for a in ax.flat:
                a.axvline(self.impact["time"], color="0.6", ls=":", lw=1)
        title = (f"yade-flex wire_and_ring: ball {self.m_ball:.1f} kg dropped {self.p['drop_height']:g} m on a ring "
                 f"({self.m_ring:.2f} kg) standing on a clamped wire (r = {1e3 * self.r_wire:g} mm)")
        if status_code != 0:
            title += f"\nSTOPPED at t = {O.time:.4f} s: {self.stop_short or status_msg.splitlines()[0][:120]}"
        fig.suptitle(title, fontsize=10, color="k" if status_code == 0 else "C3")
        fig.savefig(path, dpi=110)
        plt.close(fig)


def main():
    args = parse_args(sys.argv[1:])
    demo = Demo(args)
    demo.run()
    code, msg = demo.stop if demo.stop else (0, f"completed {demo.duration:g} s of simulated time")
    if code != 0:
        print(f"STOPPED: {msg}", flush=True)
    s = demo.write(args.out, code, msg)
    print(f"done: {s['steps']} steps in {s['wall_time_s']:.1f} s wall ({s['time_per_step_us'] or 0:.1f} us/step); "
          f"peak ball contact force {s['peak_ball_contact_force_N']:.4g} N, wire axial {s['peak_wire_axial_force_N']:.4g} N, "
          f"ring axial {s['peak_ring_axial_force_N']:.4g} N, max mid-span deflection {1e3 * s['max_midspan_deflection_m']:.2f} mm, "
          f"max |energy residual| {100 * s['max_energy_residual_rel_reference']:.3f}% of {demo.E_ref:.2f} J", flush=True)
    if s["pass_through_count"]:
        print(f"WARNING: {s['pass_through_count']} pass-through events (see summary.json)", flush=True)
    print(f"results in {os.path.abspath(args.out)}", flush=True)
    return code


# YADE runs this file with -x (exec'd as a script): no __main__ guard.
try:
    _rc = main()
except SystemExit:
    raise
except Exception:
    traceback.print_exc()
    _rc = 1
sys.stdout.flush()
sys.exit(_rc)
