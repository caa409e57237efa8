"""Checks of report.py's merging of rounds (ci/bench-peers.sh --rounds), run by ci/test.sh:
python3 -m unittest discover -s ci/peers -p 'test_*.py'. Standard library only."""
import json
import os
import tempfile
import types
import unittest

from report import Report, Results, merge_rounds


def row(ratio, work="w", peer_job="p", shadelab_job="s", figure=None):
    return dict(section="sec", work=work, peer="peer", peer_figure=figure or f"fig {ratio}",
                shadelab_figure="x", ratio=ratio, peer_job=peer_job, shadelab_job=shadelab_job)


class MergeRounds(unittest.TestCase):
    def test_the_ratio_is_the_rounds_median_with_the_figures_of_the_round_nearest_it(self):
        merged = merge_rounds([[row(0.30)], [row(0.20)], [row(0.26)]])
        self.assertEqual(len(merged), 1)
        self.assertEqual(merged[0]["ratio"], 0.26)
        self.assertEqual(merged[0]["peer_figure"], "fig 0.26")
        self.assertEqual((merged[0]["ratio_min"], merged[0]["ratio_max"]), (0.20, 0.30))
        self.assertEqual(merged[0]["ratio_rounds"], [0.30, 0.20, 0.26])

    def test_rows_are_matched_by_their_jobs_and_place_not_by_their_order_in_a_round(self):
        first = [row(1.0, work="a"), row(2.0, work="b"), row(3.0, work="b")]
        second = [row(2.2, work="b"), row(1.2, work="a"), row(3.2, work="b")]
        merged = merge_rounds([first, second])
        self.assertEqual([m["work"] for m in merged], ["a", "b", "b"])
        self.assertEqual([m["ratio"] for m in merged], [1.1, 2.1, 3.1])

    def test_a_round_without_a_figure_does_not_count(self):
        merged = merge_rounds([[row(None)], [row(0.5)], [row(None)]])
        self.assertEqual(merged[0]["ratio"], 0.5)
        self.assertEqual(merged[0]["ratio_rounds"], [None, 0.5, None])
        self.assertIsNone(merge_rounds([[row(None)], [row(None)]])[0]["ratio"])

    def test_a_row_only_a_later_round_has_is_kept(self):
        merged = merge_rounds([[row(1.0, work="a")], [row(1.0, work="a"), row(4.0, work="c")]])
        self.assertEqual([(m["work"], m["ratio"]) for m in merged], [("a", 1.0), ("c", 4.0)])


class TimeToImage(unittest.TestCase):
    def rows(self, bench, peers=None):
        jobs = {"image-default.shadelab": bench}
        jobs.update(peers or {})
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "jobs.tsv"), "w") as f:
                f.write("name\tkind\tstatus\trc\tseconds\n")
                for name in jobs:
                    f.write(f"{name}\tshadelab\tok\t0\t9\n")
            for name, out in jobs.items():
                with open(os.path.join(d, f"{name}.json"), "w") as f:
                    f.write(json.dumps(out) + "\n")
            args = types.SimpleNamespace(size=1024, smoke=False, segs=[100])
            report = Report(Results(d), args)
            report.time_to_image()
            return report.rows

    def test_warm_and_cold_are_held_to_the_cpu_twins_command_and_cold_to_warm(self):
        bench = {"scene": "default", "width": 640, "height": 480, "results": [
            {"shading": "raytrace", "time_to_image": {"warm_ms": 120.0, "cold_ms": 600.0, "cpu_ms": 90.0}}]}
        rows = self.rows(bench)
        self.assertEqual([r["ratio"] for r in rows], [0.75, 0.15, 0.2])
        self.assertIn("640x480", rows[0]["work"])
        self.assertIn("warm caches", rows[0]["work"])
        self.assertIn("empty caches", rows[1]["work"])
        self.assertEqual(rows[2]["peer"], "the same command, warm caches")

    def test_a_peers_first_image_is_held_to_the_command_cold_to_cold_and_warm_to_warm(self):
        bench = {"scene": "default", "width": 640, "height": 480, "results": [
            {"shading": "raytrace", "time_to_image": {"warm_ms": 100.0, "cold_ms": 400.0, "cpu_ms": 90.0}}]}
        peers = {"image-default.wgpu": {"cold_image_ms": 300.0, "warm_image_ms": 250.0}}
        rows = self.rows(bench, peers)
        self.assertEqual(len(rows), 5)
        cold, warm = rows[3], rows[4]
        self.assertEqual((cold["ratio"], warm["ratio"]), (0.75, 2.5))
        self.assertIn("empty caches", cold["peer"])
        self.assertIn("empty caches", cold["work"])
        self.assertIn("warm caches", warm["peer"])
        self.assertEqual((cold["peer_job"], cold["shadelab_job"]), ("image-default.wgpu", "image-default.shadelab"))

    def test_a_peer_that_did_not_run_gives_no_row_and_one_without_figures_no_ratio(self):
        bench = {"scene": "default", "width": 64, "height": 64, "results": [
            {"shading": "raytrace", "time_to_image": {"warm_ms": 100.0, "cold_ms": 400.0, "cpu_ms": 90.0}}]}
        self.assertEqual(len(self.rows(bench)), 3)
        rows = self.rows(bench, {"image-default.mitsuba-llvm": {"runs": 1}})
        self.assertEqual([r["ratio"] for r in rows[3:]], [None, None])

    def test_a_result_without_the_figures_gives_no_ratio(self):
        bench = {"scene": "default", "width": 64, "height": 64, "results": [{"shading": "phong"}]}
        self.assertEqual([r["ratio"] for r in self.rows(bench)], [None, None, None])


if __name__ == "__main__":
    unittest.main()
