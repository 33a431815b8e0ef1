// Times and steps (issue 13): t_end, dt and frame_interval checked against each other, step
// counts without overflow, fixed-step runs ending exactly at t_end, and integrators stopping
// at the end of a step on an interrupt with the state reached as their last frame.
#include <gtest/gtest.h>

#include <csignal>

#include "app/Run.hpp"
#include "core/Interrupt.hpp"
#include "integrators/TimeGrid.hpp"
#include "TestModels.hpp"

using namespace flexsens;

namespace {

IntegratorSettings times(const std::string& type, double tEnd, double dt, double frame) {
  IntegratorSettings s;
  s.type = type;
  s.tEnd = tEnd;
  s.dt = dt;
  s.frameInterval = frame;
  return s;
}

std::string problemKey(const IntegratorSettings& s) {
  const auto p = checkTimes(s);
  return p ? p->key : "";
}

const char* kPendulum = R"(
dimension: 2
plane: xz
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: B, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1.0}
integrator: {type: trapezoidal, t_end: 0.3, dt: 0.1}
outputs:
  - {name: xB, node: B, component: x}
)";

}  // namespace

TEST(TimeGrid, FixedStepRunsNeedAWholeNumberOfStepsWithinTheLimit) {
  EXPECT_EQ(problemKey(times("trapezoidal", 2.0, 1e-3, 0.01)), "");
  EXPECT_EQ(problemKey(times("bdf1", 0.3, 0.1, 0.1)), "");  // 0.3/0.1 = 2.9999999999999996
  EXPECT_EQ(problemKey(times("trapezoidal", 0.5, 0.7, 0.7)), "dt");   // t_end < dt < 2 t_end
  EXPECT_EQ(problemKey(times("trapezoidal", 1.0, 2.5, 2.5)), "dt");   // dt > 2 t_end: 0 steps
  EXPECT_EQ(problemKey(times("trapezoidal", 1.0, 0.3, 0.3)), "dt");   // 3.33 steps
  EXPECT_EQ(problemKey(times("trapezoidal", 1.0, 1e-19, 0.01)), "dt");  // 1e19 steps
  EXPECT_EQ(problemKey(times("trapezoidal", 1.0, 1e-9, 0.01)), "");    // exactly the limit
  EXPECT_EQ(problemKey(times("maggi_rk4", 1.0, 0.0, 0.01)), "dt");
  const auto p = checkTimes(times("trapezoidal", 1.0, 0.3, 0.3));
  ASSERT_TRUE(p);
  EXPECT_NE(p->message.find("t_end"), std::string::npos) << p->message;
  EXPECT_NE(p->message.find("0.25"), std::string::npos) << "suggests t_end / 4: " << p->message;
}

TEST(TimeGrid, FramesAndIdasLimits) {
  EXPECT_EQ(problemKey(times("idas", 1.0, 0.0, 1e-300)), "frame_interval");
  EXPECT_EQ(problemKey(times("idas", 1.0, 0.0, 1e-6)), "");       // 1e6 frames: the limit
  EXPECT_EQ(problemKey(times("idas", 1.0, 0.0, 1e-7)), "frame_interval");
  EXPECT_EQ(problemKey(times("idas", 1.0, 1e-19, 0.01)), "dt");   // largest step: 1e19 steps
  EXPECT_EQ(problemKey(times("idas", 1.0, 5.0, 0.01)), "");       // a largest step beyond t_end is fine
  // Fixed step: a frame interval below dt gives a frame every step, not more frames.
  EXPECT_EQ(problemKey(times("bdf1", 1.0, 1e-3, 1e-300)), "");
  EXPECT_EQ(frameEvery(times("bdf1", 1.0, 1e-3, 1e-300)), 1);
  EXPECT_EQ(frameEvery(times("bdf1", 1.0, 1e-3, 0.0104)), 10);
  EXPECT_DOUBLE_EQ(frameSpacing(times("bdf1", 1.0, 1e-3, 0.0104)), 0.01);
  EXPECT_DOUBLE_EQ(frameSpacing(times("idas", 1.0, 0.0, 0.3)), 0.3);
}

TEST(TimeGrid, CountsByHand) {
  EXPECT_EQ(fixedStepCount(1.0, 1e-3), 1000);
  EXPECT_EQ(fixedStepCount(0.3, 0.1), 3);
  EXPECT_THROW(fixedStepCount(1.0, 0.3), InputError);
  EXPECT_THROW(fixedStepCount(1.0, 1e-19), InputError);
  EXPECT_EQ(outputCount(1.0, 0.3), 4);   // 0.3, 0.6, 0.9, then 1.0
  EXPECT_EQ(outputCount(1.0, 0.25), 4);  // 0.25, 0.5, 0.75, 1.0
  EXPECT_EQ(outputCount(0.1, 1.0), 1);   // only t_end
  EXPECT_THROW(outputCount(1.0, 1e-300), InputError);
}

TEST(TimeGrid, FixedStepRunEndsExactlyAtTEnd) {
  // 3 steps of 0.1 s add up to 0.30000000000000004; the last frame must say 0.3.
  const Scene sc = readSceneText(kPendulum, "pendulum.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  for (const char* type : {"trapezoidal", "bdf1", "generalized_alpha"}) {
    test::Recorder rec;
    const auto st = integrate(as, p, initialState(as, p), times(type, 0.3, 0.1, 0.1), rec);
    EXPECT_EQ(st.steps, 3) << type;
    ASSERT_EQ(rec.frames.size(), 4u) << type;
    EXPECT_EQ(rec.frames.back().x.t, 0.3) << type;
  }
}

TEST(TimeGrid, SceneAndOptionsAreCheckedWithTheKeysNamed) {
  Scene sc = readSceneText(kPendulum, "pendulum.yaml");
  RunOptions opt;
  opt.dt = 1e-19;
  try {
    applyOptions(sc, opt);
    FAIL() << "dt 1e-19 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("option --dt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("key 'integrator.dt'"), std::string::npos) << e.what();
  }
  Scene sc2 = readSceneText(kPendulum, "pendulum.yaml");
  RunOptions opt2;
  opt2.tEnd = 0.25;  // 2.5 steps of the scene's 0.1 s
  EXPECT_THROW(applyOptions(sc2, opt2), InputError);
}

TEST(Interrupts, IntegratorsStopAfterTheStepWithTheStateReachedAsLastFrame) {
  const Scene sc = readSceneText(kPendulum, "pendulum.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  for (const char* type : {"trapezoidal", "maggi_rk4", "idas"}) {
    IntegratorSettings set = times(type, 1.0, std::string(type) == "idas" ? 0.0 : 0.01, 0.5);
    set.rtol = set.atol = 1e-8;
    test::Recorder rec;
    requestInterrupt(SIGINT);
    try {
      integrate(as, p, initialState(as, p), set, rec);
      ADD_FAILURE() << type << " ignored the interrupt";
    } catch (const Interrupted& e) {
      EXPECT_EQ(e.signal, SIGINT);
      EXPECT_GT(e.t, 0.0) << type;
      EXPECT_LT(e.t, 0.5) << type << ": stopped after one step, not at the next frame";
      ASSERT_EQ(rec.frames.size(), 2u) << type;  // the start and the state reached
      EXPECT_EQ(rec.frames.back().x.t, e.t) << type;
    }
    clearInterrupt();
  }
}
