// Barometer factor (rio/barometer.hpp): pressure -> height at known answers, residual values
// and Jacobians vs numeric differences, the sequence format, and the odometry's height on a
// simulated drive whose radar extrinsic is pitched by 1 deg (the TI loop's vertical drift:
// a tilted Doppler direction), without and with the simulated barometer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iostream>

#include "coral_introspection/eval/rio_simulation.hpp"
#include "coral_introspection/rio/barometer.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "coral_introspection/rio/estimator.hpp"
#include "rio/rio_test_utils.hpp"

using namespace coral_introspection;
using namespace coral_introspection::rio;
using rio_test::jacobianError;

TEST(RioBarometer, PressureToAltitudeKnownAnswers) {
  EXPECT_NEAR(pressureToAltitude(101325.0), 0.0, 1e-9);
  // ISA table: 1000 m -> 89874.6 Pa, 100 m -> 100129.4 Pa.
  EXPECT_NEAR(altitudeToPressure(1000.0), 89874.6, 1.0);
  EXPECT_NEAR(pressureToAltitude(100129.4), 100.0, 0.1);
  // Near the TI recording's 100.2 kPa one pascal is about 0.084 m (sign: higher = less).
  EXPECT_NEAR(pressureToAltitude(100183.0) - pressureToAltitude(100184.0), 0.0843, 0.001);
  EXPECT_NEAR(pressureToAltitude(altitudeToPressure(321.5)), 321.5, 1e-6);
}

TEST(RioBarometer, FactorValuesAndJacobians) {
  NavState s;
  s.p = Vec3(0.3, -1.0, 2.0);
  s.q = expQ(Vec3(0.2, -0.1, 0.7));
  s.v = Vec3(0.5, 0.2, -0.4);
  StateBlocks x;
  toBlocks(s, &x);
  double bias[1] = {0.25};
  // r = (p_z + v_z (tau - t) + b - h) / sigma = (2.0 + (-0.4)(-0.05) + 0.25 - 2.1) / 0.2
  const BaroFactor f(2.1, -0.05, 0.2);
  double const* params[] = {x.pose, x.speed_bias, bias};
  double r = 0.0;
  ASSERT_TRUE(f.Evaluate(params, &r, nullptr));
  EXPECT_NEAR(r, (2.0 + 0.02 + 0.25 - 2.1) / 0.2, 1e-12);
  EXPECT_LT(jacobianError(f, {x.pose, x.speed_bias, bias}), 1e-6);

  double b0[1] = {0.1}, b1[1] = {0.13};
  const BaroBiasWalkFactor w(0.01);
  double const* wp[] = {b0, b1};
  ASSERT_TRUE(w.Evaluate(wp, &r, nullptr));
  EXPECT_NEAR(r, 3.0, 1e-9);
  EXPECT_LT(jacobianError(w, {b0, b1}), 1e-6);
}

TEST(RioBarometer, ConfigKeysAndValidation) {
  RioConfig cfg;
  EXPECT_FALSE(cfg.barometer.enabled);  // off by default
  std::string err;
  YAML::Node root = YAML::Load(
      "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n"
      "barometer: {enabled: true, sigma: 0.4, bias_walk: 0.001}\n");
  ASSERT_TRUE(loadRioConfig(root, &cfg, &err)) << err;
  EXPECT_TRUE(cfg.barometer.enabled);
  EXPECT_EQ(cfg.barometer.sigma, 0.4);
  EXPECT_EQ(cfg.barometer.bias_walk, 0.001);
  root["barometer"]["sigm"] = 0.3;
  EXPECT_FALSE(loadRioConfig(root, &cfg, &err));
  EXPECT_EQ(err, "unknown key barometer/sigm (did you mean sigma?)");
  root["barometer"].remove("sigm");
  root["barometer"]["sigma"] = 0.0;
  EXPECT_FALSE(loadRioConfig(root, &cfg, &err));
  EXPECT_NE(err.find("sigma"), std::string::npos) << err;
}

namespace {

struct HeightRun {
  double vertical_rmse = 0.0, end_dz = 0.0;  // vs ground truth, relative to the first pose
  long tracked = 0, baro_frames = 0;
  std::vector<FrameReport> reports;
};

HeightRun runHeight(const eval::RioSimConfig& sim, const eval::RioSequence& seq, bool baro,
                    double pitch_error) {
  RioConfig cfg;
  cfg.extrinsics = sim.extrinsics;
  // The radar's extrinsic as a slightly wrong calibration would give it.
  cfg.extrinsics.R = cfg.extrinsics.R * Eigen::AngleAxisd(pitch_error, Vec3::UnitY());
  cfg.uncertainty.noise = sim.point_noise;
  cfg.barometer.enabled = baro;
  // Iteration-bounded solves (not the 0.05 s time limit): the same on a loaded machine.
  cfg.solver.max_solver_time = 10.0;
  Estimator est(cfg);
  HeightRun out;
  auto add = [&](const std::vector<FrameReport>& r) {
    out.reports.insert(out.reports.end(), r.begin(), r.end());
  };
  eval::replay(
      seq, [&](const ImuSample& s) { add(est.addImu(s)); },
      [&](const RadarFrame& f) { add(est.addRadar(f)); },
      [&](const BaroSample& b) { est.addBaro(b); });
  double z0 = 0.0, g0 = 0.0, sum = 0.0;
  for (const FrameReport& r : out.reports) {
    if (r.status != FrameStatus::kTracking) continue;
    const std::size_t k = static_cast<std::size_t>(std::lround(r.t * sim.radar_rate)) - 1;
    const double gz = seq.ground_truth.at(k).p.z();
    if (out.tracked++ == 0) z0 = r.state.p.z(), g0 = gz;
    out.end_dz = (r.state.p.z() - z0) - (gz - g0);
    sum += out.end_dz * out.end_dz;
  }
  out.vertical_rmse = std::sqrt(sum / std::max<long>(out.tracked, 1));
  out.baro_frames = est.counters().baro_frames;
  return out;
}

class BarometerDrive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim_ = eval::RioSimConfig::vehicle(1);
    sim_.duration = 40.0;  // 3 s at rest, 34 s driving, 3 s at rest
    sim_.barometer = true;
    seq_ = eval::simulateRio(sim_);
  }
  static eval::RioSimConfig sim_;
  static eval::RioSequence seq_;
};
eval::RioSimConfig BarometerDrive::sim_;
eval::RioSequence BarometerDrive::seq_;

}  // namespace

TEST_F(BarometerDrive, PitchedRadarDriftsInHeightWithoutTheBarometerNotWithIt) {
  const double pitch = 1.0 * M_PI / 180.0;
  const HeightRun without = runHeight(sim_, seq_, false, pitch);
  const HeightRun with = runHeight(sim_, seq_, true, pitch);
  std::cout << "vertical RMSE / end error: without " << without.vertical_rmse << " / "
            << without.end_dz << " m, with " << with.vertical_rmse << " / " << with.end_dz
            << " m\n";
  ASSERT_GT(without.tracked, 350);
  ASSERT_GT(with.tracked, 350);
  EXPECT_EQ(without.baro_frames, 0);
  EXPECT_GT(with.baro_frames, 350);
  // Without: the tilted Doppler direction lifts or sinks the whole drive (metres).
  EXPECT_GT(without.vertical_rmse, 0.5) << without.end_dz;
  EXPECT_GT(std::abs(without.end_dz), 1.0);
  // With (sigma 0.3 m per sample, a 0.4 m bias the odometry never sees directly): a few cm.
  EXPECT_LT(with.vertical_rmse, 0.15) << with.end_dz;
  EXPECT_LT(std::abs(with.end_dz), 0.15);
}

TEST_F(BarometerDrive, EnabledWithoutSamplesIsTheOdometryWithoutIt) {
  eval::RioSequence no_baro;  // the first 12 s, without the barometer's samples
  for (const ImuSample& s : seq_.imu)
    if (s.t <= 12.0) no_baro.imu.push_back(s);
  for (std::size_t k = 0; k < seq_.radar.size() && seq_.radar[k].t <= 12.0; ++k) {
    no_baro.radar.push_back(seq_.radar[k]);
    no_baro.ground_truth.push_back(seq_.ground_truth[k]);
  }
  const HeightRun a = runHeight(sim_, no_baro, true, 0.0);
  const HeightRun b = runHeight(sim_, no_baro, false, 0.0);
  ASSERT_EQ(a.reports.size(), b.reports.size());
  for (std::size_t k = 0; k < a.reports.size(); ++k)
    ASSERT_EQ(a.reports[k].state.p, b.reports[k].state.p) << k;
}

TEST(RioBarometer, SequenceFileKeepsTheBarometer) {
  eval::RioSequence seq;
  seq.imu.push_back({0.0, Vec3(0, 0, 9.81), Vec3::Zero()});
  seq.baro.push_back({0.01, 100183.25});
  seq.imu.push_back({0.02, Vec3(0, 0, 9.81), Vec3::Zero()});
  const std::string path = testing::TempDir() + "/baro.seq";
  std::string err;
  ASSERT_TRUE(eval::writeRioSequence(path, seq, &err)) << err;
  eval::RioSequence back;
  ASSERT_TRUE(eval::readRioSequence(path, &back, &err)) << err;
  ASSERT_EQ(back.baro.size(), 1u);
  EXPECT_NEAR(back.baro[0].t, 0.01, 1e-9);
  EXPECT_NEAR(back.baro[0].pressure, 100183.25, 1e-6);
  EXPECT_EQ(back.imu.size(), 2u);
  std::remove(path.c_str());
}
