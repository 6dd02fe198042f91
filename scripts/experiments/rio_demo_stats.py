#!/usr/bin/env python3
"""Summary of a rosbag recorded beside launch/rio_ti_demo.launch (doc/rio.md): CorAl verdicts
(alignment), the Doppler consistency test (velocity_consistency) of the odometry, per phase of
the TI recording, and the odometry's end pose.
  rosbag record -O demo.bag /alignment /velocity_consistency /odometry /diagnostics &
  roslaunch coral_introspection rio_ti_demo.launch
  scripts/experiments/rio_demo_stats.py demo.bag [ti_mmwave_rospkg_demo.bag]
With the TI bag as second argument it also compares the odometry's instantaneous velocity
(its twist, moved to the radar with the gyro rate and the lever arm) with the Doppler one."""
import sys, collections, math
import numpy as np
import rosbag
b = rosbag.Bag(sys.argv[1])
status = collections.Counter(); aligned = 0; verdicts = 0; reasons = collections.Counter()
dv = []; dvalid = 0; dcons = 0; dn = 0; chi = []
odom = []
for topic, m, t in b.read_messages():
    if topic.endswith('alignment'):
        status[m.status] += 1
        if m.valid:
            verdicts += 1; aligned += m.aligned
        elif m.reason:
            reasons[m.reason.split(':')[0][:60]] += 1
    elif topic.endswith('velocity_consistency'):
        dn += 1
        if m.valid:
            dvalid += 1; dcons += m.consistent; chi.append(m.chi2)
            a = np.array([m.velocity_odometry.x, m.velocity_odometry.y, m.velocity_odometry.z])
            d = np.array([m.velocity_doppler.x, m.velocity_doppler.y, m.velocity_doppler.z])
            dv.append(np.linalg.norm(a - d))
    elif topic.endswith('odometry'):
        odom.append(m)
print('alignment messages', sum(status.values()), dict(status))
print('verdicts %d, aligned %d (%.1f%%)' % (verdicts, aligned, 100.0 * aligned / max(verdicts, 1)))
print('no-verdict reasons', reasons.most_common(5))
print('doppler checks %d, valid %d, consistent %d (%.1f%% of valid)' % (dn, dvalid, dcons, 100.0 * dcons / max(dvalid, 1)))
if dv:
    print('|v_odom - v_doppler| median %.3f m/s, 90%% %.3f m/s; chi2 median %.2f' % (np.median(dv), np.quantile(dv, 0.9), np.median(chi)))
if odom:
    p0, p1 = odom[0].pose.pose.position, odom[-1].pose.pose.position
    def yaw(q): return math.degrees(math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)))
    print('odometry messages %d; end-point error horizontal %.4f m, vertical %.3f m, yaw %.2f deg' % (
        len(odom), math.hypot(p1.x - p0.x, p1.y - p0.y), p1.z - p0.z,
        (yaw(odom[-1].pose.pose.orientation) - yaw(odom[0].pose.pose.orientation) + 180) % 360 - 180))
# split by the recording's phases (data README): standing 0-13.7 s, moving 13.7-33.3 s, end
t0 = None
rows = []
for topic, m, t in b.read_messages(topics=['/alignment', '/velocity_consistency']):
    st = (m.stamp_b if hasattr(m, 'stamp_b') else m.header.stamp).to_sec() if topic == '/alignment' else m.header.stamp.to_sec()
    rows.append((topic, st, m))
t0 = min(r[1] for r in rows if r[1] > 0)
for name, lo, hi in [('standing 0-13.7 s', 0, 13.7), ('moving 13.7-33.3 s', 13.7, 33.3), ('end 33.3- s', 33.3, 1e9)]:
    al = [m for tp, st, m in rows if tp == '/alignment' and m.valid and lo <= st - t0 < hi]
    dc = [m for tp, st, m in rows if tp == '/velocity_consistency' and m.valid and lo <= st - t0 < hi]
    print('%s: CorAl verdicts %d, aligned %.1f%%; Doppler checks %d, consistent %.1f%%, median chi2 %.2f' % (
        name, len(al), 100.0 * np.mean([m.aligned for m in al]) if al else float('nan'), len(dc),
        100.0 * np.mean([m.consistent for m in dc]) if dc else float('nan'), np.median([m.chi2 for m in dc]) if dc else float('nan')))
mv = [m for tp, st, m in rows if tp == '/velocity_consistency' and m.valid and 13.7 <= st - t0 < 33.3]
d = [np.linalg.norm(np.array([m.velocity_odometry.x - m.velocity_doppler.x, m.velocity_odometry.y - m.velocity_doppler.y, m.velocity_odometry.z - m.velocity_doppler.z])) for m in mv]
sp = [np.linalg.norm([m.velocity_doppler.x, m.velocity_doppler.y, m.velocity_doppler.z]) for m in mv]
print('moving: |v_tf - v_doppler| median %.3f m/s (90%% %.3f), Doppler speed median %.2f m/s' % (np.median(d), np.quantile(d, 0.9), np.median(sp)))

if len(sys.argv) > 2:
    from scipy.spatial.transform import Rotation
    R = Rotation.from_quat([-0.918681231167, 0.386946837543, 0.071757109423, 0.033880048164]).as_matrix()
    tE = np.array([0.03, 0.03, -0.06])
    imu_t, imu_g = [], []
    for _, m, _ in rosbag.Bag(sys.argv[2]).read_messages(topics=['/sensor_platform/imu']):
        imu_t.append(m.header.stamp.to_sec()); imu_g.append([m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z])
    imu_t = np.array(imu_t); imu_g = np.array(imu_g)
    odo, dop = {}, {}
    for tp, m, _ in rosbag.Bag(sys.argv[1]).read_messages(topics=['/odometry', '/velocity_consistency']):
        if tp == '/odometry':
            odo[round(m.header.stamp.to_sec(), 4)] = np.array([m.twist.twist.linear.x, m.twist.twist.linear.y, m.twist.twist.linear.z])
        elif m.valid:
            dop[round(m.header.stamp.to_sec(), 4)] = (np.array([m.velocity_doppler.x, m.velocity_doppler.y, m.velocity_doppler.z]),
                                                       np.array([m.velocity_odometry.x, m.velocity_odometry.y, m.velocity_odometry.z]), m.consistent)
    t0 = imu_t[0]
    d_inst, d_tf = [], []
    for t, (vd, vtf, c) in dop.items():
        if t not in odo or not (13.7 <= t - t0 < 33.3):
            continue
        w = imu_g[np.argmin(np.abs(imu_t - t))]
        v_r = R.T @ (odo[t] + np.cross(w, tE))
        d_inst.append(np.linalg.norm(v_r - vd)); d_tf.append(np.linalg.norm(vtf - vd))
    print('moving frames %d: |v - v_doppler| median / 90%%: odometry instantaneous %.3f / %.3f m/s, TF finite difference %.3f / %.3f m/s' % (
        len(d_inst), np.median(d_inst), np.quantile(d_inst, 0.9), np.median(d_tf), np.quantile(d_tf, 0.9)))
