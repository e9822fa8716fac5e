#!/usr/bin/env python3
"""scripts/evaluate-diagnosis.py's bookkeeping: the seeds of each split stay in their ranges and
apart, the goals count what they say, a diagnosed set is not run again, and the report is
written whole (no temporary left)."""
import argparse
import importlib.util
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "evaluate-diagnosis.py")
spec = importlib.util.spec_from_file_location("evaluate_diagnosis", SCRIPT)
ev = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ev)


def args(**kw):
    base = dict(rows="", dev_sets=9, eval_sets=12, calibration=20, false_alarm=20, work="", build="/nonexistent",
                nice=15, jobs=2, speeds="1", loads="0", diagnose_arg=[], md="", csv="", unseen_noise=0)
    base.update(kw)
    return argparse.Namespace(**base)


def result(row, verdict, causes, split="evaluation", seed=1000):
    return {"split": split, "name": f"{seed:05d}_{row}", "seed": seed, "row": row, "trials": 12, "commit": "abc",
            "laws": ["noise white: sigma"], "seconds": 1.0, "rc": 0, "verdict": verdict,
            "causes": [{"effect": c[0], "gain_pct": c[1], "confirmed": c[2] if len(c) > 2 else None} for c in causes]}


class Plan(unittest.TestCase):
    def test_splits_keep_their_seed_ranges_and_never_share_a_seed(self):
        tasks = ev.plan(args())
        seeds = {}
        for split, name, seed, row, kind in tasks:
            seeds.setdefault(split, []).append(seed)
        self.assertTrue(all(1 <= s <= 999 for s in seeds["development"] + seeds["calibration"]))
        self.assertTrue(all(s >= 1000 for s in seeds["evaluation"] + seeds["false_alarm"]))
        every = [t[2] for t in tasks]
        self.assertEqual(len(every), len(set(every)))
        self.assertEqual(len(seeds["evaluation"]), 12 * len(ev.ROWS))
        kinds = [t[4] for t in tasks if t[0] == "false_alarm"]
        self.assertEqual(kinds[:5], ev.NOISE_KINDS)

    def test_unseen_noise_sets_are_development_seeds_apart_from_the_calibration(self):
        tasks = ev.plan(args(dev_sets=0, eval_sets=0, false_alarm=0, calibration=60, unseen_noise=39))
        every = [t[2] for t in tasks]
        self.assertEqual(len(every), len(set(every)))
        unseen = [t for t in tasks if t[0] == "unseen_noise"]
        self.assertTrue(all(960 <= t[2] <= 999 for t in unseen))
        self.assertEqual([t[4] for t in unseen[:5]], ev.UNSEEN_KINDS)
        with self.assertRaises(SystemExit):
            ev.plan(args(calibration=61, unseen_noise=1))

    def test_refuses_development_sets_that_would_reach_evaluation_seeds(self):
        with self.assertRaises(SystemExit):
            ev.plan(args(dev_sets=10))
        with self.assertRaises(SystemExit):
            ev.plan(args(rows="warp_drive"))


class Goals(unittest.TestCase):
    def test_goals_count_what_they_say(self):
        rs = [result("wheel_radius", "explained", [("wheel_radius", 80.0)]),
              result("inertial_pitch", "partly_explained", [("inertial_pitch", -5.0)]),   # negative gain: no
              result("marker_offset", "partly_explained", [("tyre_compliance", 50.0), ("marker_offset", 40.0)]),
              result("inertial_pitch+marker_offset", "partly_explained", [("marker_offset", 80.0, True), ("inertial_pitch", 10.0, False)]),
              result("cushion_compliance+suspension_friction", "partly_explained", [("suspension_friction", 50.0)]),
              result("tyre_compliance+inertial_pitch", "explained", [("inertial_pitch", 60.0, True), ("tyre_compliance", 5.0, True)]),
              result("none", "adequate", []), result("none", "unexplained", []),
              result("occupant_seat", "adequate", [])]
        figures = {goal: figure for goal, _, figure in ev.goals(rs)}
        self.assertEqual(figures["single effects named first with a positive held-out gain"], "1/3 (33 %)")
        self.assertEqual(figures["both causes of a pair found"], "2/3 (67 %)")
        self.assertEqual(figures["both causes of a pair found and confirmed"], "1/3 (33 %)")  # an unconfirmed cause counts above only
        self.assertEqual(figures["no-effect sets `adequate`"], "1/2 (50 %)")
        self.assertEqual(figures["outside the catalogue called `adequate`"], "1/1 (100 %)")


class Probability(unittest.TestCase):
    def test_recomputed_probabilities_follow_the_stated_posterior(self):
        # The C++ test's three models (EffectProbabilityTest): base (4, 4), {a} (1, 4) twice
        # (the better counts), {a, b} (1, 2); π = 0.2, ν = 2.
        inputs = {"models": [{"effects": [], "selection_ms": [4, 4]},
                             {"effects": ["tyre_compliance"], "selection_ms": [1, 4]},
                             {"effects": ["tyre_compliance"], "selection_ms": [2, 4]},
                             {"effects": ["inertial_pitch", "tyre_compliance"], "selection_ms": [1, 2]},
                             {"effects": ["wheel_radius"], "selection_ms": []}]}
        p = ev.probabilities(inputs, 0.2, 2.0)
        w0, wa, wab = 1 / 16, 0.25 / 4, 0.0625 / 2
        self.assertAlmostEqual(p["tyre_compliance"], (wa + wab) / (w0 + wa + wab), places=12)
        self.assertAlmostEqual(p["inertial_pitch"], wab / (w0 + wa + wab), places=12)
        self.assertEqual(p["wheel_radius"], 0.0)

    def test_reliability_bins_and_brier(self):
        pairs = [(0.05, 0), (0.05, 0), (0.05, 1), (0.95, 1), (0.95, 1), (0.5, 0)]
        bins = {k: (n, mean_p, f) for k, n, mean_p, f, lo, hi in ev.reliability(pairs)}
        self.assertEqual(bins[0][0], 3)
        self.assertAlmostEqual(bins[0][2], 1 / 3)
        self.assertEqual(bins[9], (2, 0.95, 1.0))
        self.assertEqual(bins[5][0], 1)
        self.assertAlmostEqual(ev.brier(pairs), (2 * 0.05 ** 2 + 0.95 ** 2 + 2 * 0.05 ** 2 + 0.25) / 6)
        for k, n, mean_p, f, lo, hi in ev.reliability(pairs):
            self.assertLessEqual(lo, f)
            self.assertGreaterEqual(hi, f)

    def test_pairs_count_every_catalogue_effect_and_outside_effects_as_none(self):
        r = result("occupant_seat", "partly_explained", [])
        r["probability"] = {e: 0.1 for e in ev.CATALOGUE}
        pairs = ev.probability_pairs([r])
        self.assertEqual(len(pairs), len(ev.CATALOGUE))
        self.assertTrue(all(y == 0 for _, y in pairs))
        r2 = result("inertial_pitch+marker_offset", "explained", [])
        r2["probability"] = {e: 0.5 for e in ev.CATALOGUE}
        self.assertEqual(sum(y for _, y in ev.probability_pairs([r2])), 2)


class Resume(unittest.TestCase):
    def test_a_diagnosed_set_is_not_run_again_and_the_report_is_written_whole(self):
        with tempfile.TemporaryDirectory() as work:
            os.makedirs(os.path.join(work, "results"))
            done = result("none", "adequate", [])
            with open(os.path.join(work, "results", done["name"] + ".json"), "w") as f:
                json.dump(done, f)
            # The build folder does not exist: running anything would raise.
            r, skipped = ev.run_set(args(work=work), ("evaluation", done["name"], 1000, "none", ""), "abc")
            self.assertTrue(skipped)
            self.assertEqual(r["verdict"], "adequate")
            a = args(work=work, md=os.path.join(work, "t.md"), csv=os.path.join(work, "t.csv"), nice=15, jobs=2)
            ev.report(a, [r])
            self.assertIn("| no-effect sets `adequate` | ≥ 95 % | – | 1/1 (100 %) |", open(a.md).read())
            self.assertEqual(len(open(a.csv).read().splitlines()), 2)
            self.assertFalse([f for f in os.listdir(work) if f.endswith(".tmp")])


if __name__ == "__main__":
    unittest.main()
