#!/usr/bin/python3
# pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
# SPDX-License-Identifier: BSD-3-Clause
#
# rostest client for denoise_node (started by denoise.test in three configurations):
# sends noisy clouds of a plane with outliers and checks what comes back: the header
# (frame and stamp to the nanosecond), every field and the order of the points,
# outliers removed, points moved toward the plane, and that bad clouds and bad
# parameters give an error and no output instead of a crash.
#
# /usr/bin/python3, not `env python3`: the ROS Python modules are Debian's.
import math
import random
import struct
import subprocess
import threading
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import PointCloud2, PointField

PKG = "pcl_graph_denoise_ros"
TIMEOUT = 30.0  # seconds for an answer (the clouds take milliseconds)

# A PointXYZRGB-like layout with padding and a custom field: x, y, z, pad, rgb, id.
FIELDS = [
    PointField("x", 0, PointField.FLOAT32, 1),
    PointField("y", 4, PointField.FLOAT32, 1),
    PointField("z", 8, PointField.FLOAT32, 1),
    PointField("rgb", 16, PointField.FLOAT32, 1),
    PointField("id", 20, PointField.UINT32, 1),
]
POINT_STEP = 24

GRID = 40            # inliers: a GRID x GRID grid on the plane z = 0
SPACING = 0.025      # metres
NOISE = 0.004        # standard deviation of z
OUTLIERS = 80        # uniform, 0.1 to 0.4 m off the plane


def colour(i):
    """The rgb bits of point i: distinct, top byte 0 (never a NaN float)."""
    return (i * 2654435761) & 0xFFFFFF


def make_cloud(points, stamp, frame="test_frame", width=None, height=1, fields=FIELDS,
               point_step=POINT_STEP):
    """points: list of (id, x, y, z)."""
    data = bytearray(point_step * len(points))
    for n, (i, x, y, z) in enumerate(points):
        base = n * point_step
        for f in fields:
            if f.name in ("x", "y", "z"):
                struct.pack_into("<f", data, base + f.offset, {"x": x, "y": y, "z": z}[f.name])
            elif f.name == "rgb":
                struct.pack_into("<I", data, base + f.offset, colour(i))
            elif f.name == "id":
                struct.pack_into("<I", data, base + f.offset, i)
    msg = PointCloud2()
    msg.header.stamp = stamp
    msg.header.frame_id = frame
    msg.height = height
    msg.width = len(points) // height if width is None else width
    msg.fields = fields
    msg.is_bigendian = False
    msg.point_step = point_step
    msg.row_step = point_step * msg.width
    msg.data = bytes(data)
    msg.is_dense = all(math.isfinite(c) for p in points for c in p[1:])
    return msg


def read_cloud(msg):
    """{id: (x, y, z, rgb bits)} and the ids in order."""
    offset = {f.name: f.offset for f in msg.fields}
    ids, points = [], {}
    for n in range(msg.width * msg.height):
        row, column = divmod(n, msg.width)
        base = row * msg.row_step + column * msg.point_step
        x, y, z = (struct.unpack_from("<f", msg.data, base + offset[c])[0] for c in "xyz")
        rgb = struct.unpack_from("<I", msg.data, base + offset["rgb"])[0]
        i = struct.unpack_from("<I", msg.data, base + offset["id"])[0]
        ids.append(i)
        points[i] = (x, y, z, rgb)
    return points, ids


def plane(seed, outliers=OUTLIERS, nan_ids=()):
    """Noisy plane points (ids 0 .. GRID^2 - 1), then the outliers."""
    rng = random.Random(seed)
    points = []
    for r in range(GRID):
        for c in range(GRID):
            i = r * GRID + c
            if i in nan_ids:
                points.append((i, math.nan, math.nan, math.nan))
            else:
                points.append((i, c * SPACING, r * SPACING, rng.gauss(0.0, NOISE)))
    extent = (GRID - 1) * SPACING
    for k in range(outliers):
        z = rng.uniform(0.1, 0.4) * rng.choice((-1.0, 1.0))
        points.append((GRID * GRID + k, rng.uniform(0, extent), rng.uniform(0, extent), z))
    return points


def rms_z(points, ids):
    return math.sqrt(sum(points[i][2] ** 2 for i in ids) / len(ids))


class Answers:
    """The clouds a node publishes on one topic, looked up by stamp."""

    def __init__(self, topic):
        self.clouds = []
        self.cond = threading.Condition()
        self.sub = rospy.Subscriber(topic, PointCloud2, self.received, queue_size=100)

    def received(self, msg):
        with self.cond:
            self.clouds.append(msg)
            self.cond.notify_all()

    def stamps(self):
        with self.cond:
            return [m.header.stamp for m in self.clouds]

    def wait_for(self, stamp, timeout=TIMEOUT):
        deadline = rospy.get_time() + timeout
        with self.cond:
            while True:
                for m in self.clouds:
                    if m.header.stamp == stamp:
                        return m
                left = deadline - rospy.get_time()
                if left <= 0:
                    return None
                self.cond.wait(left)


class Errors:
    """ERROR messages on /rosout, per node."""

    def __init__(self):
        self.messages = []
        self.cond = threading.Condition()
        self.sub = rospy.Subscriber("/rosout", Log, self.received, queue_size=1000)

    def received(self, log):
        if log.level >= Log.ERROR:
            with self.cond:
                self.messages.append((log.name, log.msg))
                self.cond.notify_all()

    def wait_for(self, node, text, timeout=TIMEOUT):
        deadline = rospy.get_time() + timeout
        with self.cond:
            while True:
                for name, msg in self.messages:
                    if name == node and text in msg:
                        return msg
                left = deadline - rospy.get_time()
                if left <= 0:
                    return None
                self.cond.wait(left)


class Node:
    """A denoise_node of denoise.test, by namespace."""

    def __init__(self, ns):
        self.name = "/%s/pcl_graph_denoise" % ns
        self.pub = rospy.Publisher("/%s/input" % ns, PointCloud2, queue_size=100)
        self.answers = Answers("/%s/output" % ns)

    def connect(self, test):
        deadline = rospy.get_time() + TIMEOUT
        while rospy.get_time() < deadline and not rospy.is_shutdown():
            if self.pub.get_num_connections() > 0 and self.answers.sub.get_num_connections() > 0:
                return
            rospy.sleep(0.05)
        test.fail("%s did not connect to /input and /output within %g s" % (self.name, TIMEOUT))

    def send(self, test, msg):
        self.connect(test)
        self.pub.publish(msg)

    def denoise(self, test, msg):
        self.send(test, msg)
        answer = self.answers.wait_for(msg.header.stamp)
        test.assertIsNotNone(answer, "%s published no answer within %g s" % (self.name, TIMEOUT))
        return answer


_stamp_counter = [0]


def new_stamp():
    """Distinct stamps with nanoseconds that PCL's microsecond header would lose."""
    _stamp_counter[0] += 1
    return rospy.Time(1700000000 + _stamp_counter[0], 123456789)


class TestDenoiseNode(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_denoise", anonymous=True)
        cls.errors = Errors()
        cls.default = Node("default")      # chain outliers -> tv, data-derived defaults
        cls.tikhonov = Node("tikhonov")    # chain [tikhonov], k from ~tikhonov/k
        cls.steps = Node("steps")          # chain of dictionaries
        cls.organized = Node("organized")  # outliers kept as NaN, then tv
        cls.everything = Node("everything")  # outlier_fraction 1: nothing left for tv

    def check_same_layout(self, sent, answer):
        self.assertEqual(answer.header.frame_id, sent.header.frame_id)
        self.assertEqual(answer.header.stamp, sent.header.stamp)  # to the nanosecond
        self.assertEqual([(f.name, f.offset, f.datatype, f.count) for f in answer.fields],
                         [(f.name, f.offset, f.datatype, f.count) for f in sent.fields])
        self.assertEqual(answer.point_step, sent.point_step)
        self.assertFalse(answer.is_bigendian)

    def test_default_chain_removes_outliers_and_smooths(self):
        points = plane(seed=1)
        sent = make_cloud(points, new_stamp())
        answer = self.default.denoise(self, sent)
        self.check_same_layout(sent, answer)
        self.assertEqual(answer.height, 1)
        before, _ = read_cloud(sent)
        after, ids = read_cloud(answer)
        self.assertEqual(ids, sorted(ids), "the order of the points is kept")
        self.assertTrue(set(ids) <= set(before))
        inliers = [i for i in ids if i < GRID * GRID]
        outliers_left = len(ids) - len(inliers)
        inliers_removed = GRID * GRID - len(inliers)
        rospy.loginfo("default chain: %d -> %d points, %d of %d outliers left, %d inliers "
                      "removed, rms z %.5f -> %.5f", len(points), len(ids), outliers_left,
                      OUTLIERS, inliers_removed, rms_z(before, inliers), rms_z(after, inliers))
        self.assertLess(len(ids), len(points))
        self.assertLessEqual(outliers_left, OUTLIERS // 10)
        self.assertLessEqual(inliers_removed, GRID * GRID // 50)
        self.assertLess(rms_z(after, inliers), 0.7 * rms_z(before, inliers),
                        "points move toward the plane")
        drift = max(math.hypot(after[i][0] - before[i][0], after[i][1] - before[i][1])
                    for i in inliers)
        self.assertLess(drift, SPACING / 2, "points do not slide along the plane")
        for i in ids:
            self.assertEqual(after[i][3], before[i][3], "rgb of point %d kept" % i)

    def test_tikhonov_keeps_size_organisation_and_non_finite_points(self):
        nan_ids = {5, 100, 777}
        points = plane(seed=2, outliers=0, nan_ids=nan_ids)
        sent = make_cloud(points, new_stamp(), width=GRID, height=GRID)
        self.assertFalse(sent.is_dense)
        answer = self.tikhonov.denoise(self, sent)
        self.check_same_layout(sent, answer)
        self.assertEqual((answer.width, answer.height), (GRID, GRID))
        self.assertFalse(answer.is_dense)
        before, _ = read_cloud(sent)
        after, ids = read_cloud(answer)
        self.assertEqual(ids, [p[0] for p in points], "same points in the same order")
        for i in nan_ids:
            self.assertTrue(all(math.isnan(c) for c in after[i][:3]), "point %d stays NaN" % i)
        finite = [i for i in ids if i not in nan_ids]
        rospy.loginfo("tikhonov: rms z %.5f -> %.5f", rms_z(before, finite), rms_z(after, finite))
        self.assertLess(rms_z(after, finite), 0.7 * rms_z(before, finite))
        self.assertTrue(all(after[i][3] == before[i][3] for i in ids), "rgb kept")

    def test_chain_of_dictionaries(self):
        # [{step: outliers, outlier_fraction: 0.05}, {step: tv, k: 12}]: 5% removed.
        points = plane(seed=3)
        sent = make_cloud(points, new_stamp(), frame="another_frame")
        answer = self.steps.denoise(self, sent)
        self.check_same_layout(sent, answer)
        before, _ = read_cloud(sent)
        after, ids = read_cloud(answer)
        removed = len(points) - len(ids)
        self.assertAlmostEqual(removed, 0.05 * len(points), delta=2)
        self.assertLessEqual(len(ids) - sum(1 for i in ids if i < GRID * GRID), OUTLIERS // 10)
        inliers = [i for i in ids if i < GRID * GRID]
        self.assertLess(rms_z(after, inliers), 0.7 * rms_z(before, inliers))

    def test_outliers_kept_organized_as_nan(self):
        # An organised GRID x GRID cloud whose points 7, 27, 47, ... are outliers.
        rng = random.Random(5)
        moved = set(range(7, GRID * GRID, 20))
        points = [(i, x, y, z if i not in moved else rng.uniform(0.1, 0.4))
                  for i, x, y, z in plane(seed=5, outliers=0)]
        sent = make_cloud(points, new_stamp(), width=GRID, height=GRID)
        answer = self.organized.denoise(self, sent)
        self.check_same_layout(sent, answer)
        self.assertEqual((answer.width, answer.height), (GRID, GRID))
        self.assertFalse(answer.is_dense)
        before, _ = read_cloud(sent)
        after, ids = read_cloud(answer)
        self.assertEqual(ids, [p[0] for p in points])
        gone = {i for i in ids if math.isnan(after[i][2])}
        self.assertEqual(len(gone), len(moved))  # outlier_fraction 0.05 of 1600 = 80
        self.assertGreaterEqual(len(gone & moved), len(moved) - 4)
        self.assertTrue(all(after[i][3] == before[i][3] for i in ids), "rgb kept, also as NaN")

    def test_no_point_left_gives_an_empty_cloud(self):
        sent = make_cloud(plane(seed=6), new_stamp())
        answer = self.everything.denoise(self, sent)
        self.check_same_layout(sent, answer)
        self.assertEqual(answer.width * answer.height, 0)
        self.assertEqual(len(answer.data), 0)

    def test_bad_clouds_give_an_error_and_no_output(self):
        good = plane(seed=4)
        no_z = [f for f in FIELDS if f.name != "z"]
        truncated = make_cloud(good, new_stamp())
        truncated.data = truncated.data[: len(truncated.data) // 2]
        outside = make_cloud(good, new_stamp(), fields=FIELDS + [
            PointField("extra", 22, PointField.FLOAT32, 1)])
        bad = [
            ("the cloud is empty", make_cloud([], new_stamp())),
            ("no 'z' field", make_cloud(good, new_stamp(), fields=no_z)),
            ("truncated", truncated),
            ("does not fit in point_step", outside),
            ("no point has a finite x, y, z",
             make_cloud([(i, math.nan, math.nan, math.nan) for i in range(50)], new_stamp())),
        ]
        for _, msg in bad:
            self.default.send(self, msg)
        # The node handles its input in order: once the good cloud is answered, every bad
        # one has been handled, and none of them was published.
        sent = make_cloud(good, new_stamp())
        self.default.denoise(self, sent)
        published = self.default.answers.stamps()
        for why, msg in bad:
            self.assertNotIn(msg.header.stamp, published, "a cloud with '%s' was published" % why)
            stamp = "stamp %d.%09d" % (msg.header.stamp.secs, msg.header.stamp.nsecs)
            error = self.errors.wait_for(self.default.name, stamp)
            self.assertIsNotNone(error, "no ROS_ERROR for the cloud with '%s'" % why)
            self.assertIn(why, error)

    def test_invalid_parameters_stop_the_node(self):
        # (private parameters, command-line arguments, expected message)
        cases = [
            ({"chain": ["outliers", "bogus"]}, [], "~chain[1]: unknown step 'bogus'"),
            ({}, ["_chain:=outliers,bogus"], "~chain: unknown step 'bogus'"),
            ({"chain": "outliers"}, ["_outlier_fraction:=2"],
             "~outlier_fraction: expected a number in [0, 1], got 2"),
            ({"chain": [{"step": "tv", "k": 0}]}, [], "~chain[0]/k: expected an integer >= 1"),
            ({}, ["_chain:=tikhonov", "_tikhonov/k:=0"], "~tikhonov/k: expected an integer >= 1"),
            ({"chain": [{"step": "tv", "graph_iterations": 1001}]}, [],
             "~chain[0]/graph_iterations: expected an integer in [1, 1000], got 1001"),
            ({"chain": ["tikhonov"], "tv": {"gama": 0.01}}, [],
             "~tv/gama: not a parameter of a 'tv' step"),
            ({"treads": 1}, [], "~treads: not a parameter of this node"),
            ({"outliers": {"threshold_ratio": 0.3}, "outlier_fraction": 0.1}, [],
             "give at most one of threshold_ratio, degree_threshold and outlier_fraction"),
            ({"gamma": -1}, [], "~gamma: expected a number >= 0 or 'auto', got -1"),
            ({"chain": ["outliers"], "outliers": {"residual_threshold": -1}}, [],
             "~outliers/residual_threshold: expected a number >= 0 (0 = off), got -1"),
            ({"tikhonov": {"solver": "lu"}, "chain": ["tikhonov"]}, [],
             "~tikhonov/solver: expected 'cg' or 'cholmod', got 'lu'"),
        ]
        for n, (parameters, arguments, expected) in enumerate(cases):
            name = "bad_parameters_%d" % n
            for key, value in parameters.items():
                rospy.set_param("/%s/%s" % (name, key), value)
            run = subprocess.run(
                ["rosrun", PKG, "denoise_node", "__name:=" + name] + arguments,
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=60,
                universal_newlines=True)
            self.assertEqual(run.returncode, 1, "%s %s: %s" % (parameters, arguments, run.stdout))
            self.assertIn(expected, run.stdout, "%s %s" % (parameters, arguments))

if __name__ == "__main__":
    rostest.rosrun(PKG, "test_denoise", TestDenoiseNode)
