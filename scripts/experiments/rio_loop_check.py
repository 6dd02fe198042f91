#!/usr/bin/env python3
"""Radar check of the TI loop's end pose: the static reflectors seen at the start (standing,
0.5-10.5 s) and at the end (34 s - end), each placed in the odometry frame with the
trajectory, registered to each other (yaw + translation, z kept, nearest-neighbour ICP with a
trimmed cost). The registration's yaw is the odometry's heading error at the end measured by
the radar, independent of the assumption that the device ends where it started (doc/rio.md).
  scripts/experiments/rio_loop_check.py --bag ../shared/data/ti_mmwave_demo/ti_mmwave_rospkg_demo.bag \
      --trajectory /tmp/ti.tum --dz 1.34
Extrinsics: those of config/rio_ti_mmwave.yaml; scan times: same-seq trigger + 9.25 ms."""
import sys
import numpy as np
import rosbag
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

import argparse
ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--bag", required=True, help="ti_mmwave_rospkg_demo.bag")
ap.add_argument("--trajectory", required=True, help="rio_offline --output TUM file")
ap.add_argument("--dz", type=float, default=0.0,
                help="[m] added to the end points' height (undoes the odometry's vertical drift)")
ap.add_argument("--induce-yaw", type=float, default=0.0,
                help="[deg] sensitivity check: end points turned by this much about the start "
                     "position first; the correction found should be its negative")
args = ap.parse_args()
bag, tum = args.bag, args.trajectory
R_b_ti = Rotation.from_quat([-0.918681231167, 0.386946837543, 0.071757109423, 0.033880048164]).as_matrix()
t_b_ti = np.array([0.03, 0.03, -0.06])
traj = np.loadtxt(tum)
b = rosbag.Bag(bag)
trig, scans = {}, {}
for topic, m, _ in b.read_messages(topics=['/sensor_platform/radar_right/trigger', '/ti_mmwave/radar_scan_pcl']):
    if topic.endswith('trigger'):
        trig[m.seq] = m.stamp.to_sec()
    else:
        import sensor_msgs.point_cloud2 as pc2
        scans[m.header.seq] = np.array([p[:3] for p in pc2.read_points(m, field_names=('x', 'y', 'z'))])
t0 = min(trig.values())
def world_points(lo, hi):
    out = []
    for seq, pts in scans.items():
        if seq not in trig or len(pts) == 0:
            continue
        t = trig[seq] + 0.00925
        if not (lo <= t - t0 < hi):
            continue
        i = np.argmin(np.abs(traj[:, 0] - t))
        if abs(traj[i, 0] - t) > 0.01:
            continue
        R = Rotation.from_quat(traj[i, 4:8]).as_matrix()
        r = np.linalg.norm(pts, axis=1)
        pts = pts[(r > 0.25)]
        out.append((R @ (R_b_ti @ pts.T + t_b_ti[:, None])).T + traj[i, 1:4])
    return np.vstack(out)
A = world_points(0.5, 10.5)
B = world_points(34.0, 1e9)
B[:, 2] += args.dz
if args.induce_yaw:
    c, s_ = np.cos(np.radians(args.induce_yaw)), np.sin(np.radians(args.induce_yaw))
    xy = B[:, :2] - traj[0, 1:3]
    B[:, :2] = xy @ np.array([[c, s_], [-s_, c]]) + traj[0, 1:3]
print('start points %d, end points %d' % (len(A), len(B)))
tree = cKDTree(A)
def icp(yaw0):
    yaw, t = yaw0, np.zeros(2)
    for _ in range(30):
        c, s = np.cos(yaw), np.sin(yaw)
        P = B.copy()
        P[:, :2] = B[:, :2] @ np.array([[c, s], [-s, c]]) + t
        d, j = tree.query(P)
        keep = d < np.quantile(d, 0.6)
        # 2D Procrustes on the kept pairs (xy)
        X, Y = B[keep, :2], A[j[keep], :2]
        mx, my = X.mean(0), Y.mean(0)
        H = (X - mx).T @ (Y - my)
        yaw = np.arctan2(H[0, 1] - H[1, 0], H[0, 0] + H[1, 1])
        c, s = np.cos(yaw), np.sin(yaw)
        t = my - mx @ np.array([[c, s], [-s, c]])
    P = B.copy()
    P[:, :2] = B[:, :2] @ np.array([[c, s], [-s, c]]) + t
    d, _ = tree.query(P)
    return np.mean(d < 0.3), yaw, t
res = sorted((icp(np.radians(y0)) for y0 in np.arange(-10, 10.1, 1.0)), key=lambda r: -r[0])
for inl, yaw, t in res[:3]:
    print('inliers(<0.3 m) %.3f yaw correction %.2f deg translation %.3f %.3f m' % (inl, np.degrees(yaw), t[0], t[1]))
d, _ = tree.query(B)
print('without correction: inliers %.3f' % np.mean(d < 0.3))
for name, P in (('start', A), ('end', B)):
    c = np.median(P, axis=0)
    ang = np.degrees(np.arctan2(P[:, 1] - traj[0, 2], P[:, 0] - traj[0, 1]))
    print(name, 'median point %s, bearing from start position: median %.1f deg, IQR %.1f..%.1f' % (c.round(2), np.median(ang), *np.quantile(ang, [0.25, 0.75])))
# directional overlap: nearest distance distribution
d, _ = tree.query(B)
print('end->start nearest distance quantiles 10/50/90: %s m' % np.quantile(d, [0.1, 0.5, 0.9]).round(2))
dA, _ = cKDTree(A[: len(A) // 2]).query(A[len(A) // 2:])
print('start second half -> first half: %s m' % np.quantile(dA, [0.1, 0.5, 0.9]).round(2))
