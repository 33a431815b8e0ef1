// Undamped meshed bodies skip the dQ/dv pass of the sensitivity runs (issue 41, item 2). Their
// elements declare it (velocityDependent() false: no mass or Kelvin-Voigt damping can be nonzero)
// and the assembly leaves them out when only dQ/dv is wanted. References: the declaration against
// AD's dQ/dv (exactly zero when declared, nonzero for each damping), and a sensitivity run of
// the undamped solid pendulum (examples/solid/pendulum3d.yaml, coarsened) against the same run
// with every element declaring itself velocity-dependent, as it did before: the same series to
// round-off, and the second run's extra force-Jacobian calls are exactly one per element per dQ/dv
// pass, which the first run does not make.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <memory>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "elements/ShellClampHinge.hpp"
#include "elements/ShellHinge.hpp"
#include "elements/ShellTriangle.hpp"
#include "elements/Solid.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

/// An element that forwards everything to the one it wraps and counts its forceJacobian calls;
/// velocityDependent() is the wrapped element's, or true when `declareDamped`.
class CountingElement : public Element {
 public:
  CountingElement(std::unique_ptr<Element> inner, bool declareDamped, long& jacobianCalls)
      : Element(inner->name(), inner->nodes()), inner_(std::move(inner)), declareDamped_(declareDamped),
        calls_(jacobianCalls) {}
  std::string kind() const override { return inner_->kind(); }
  int gradients() const override { return inner_->gradients(); }
  bool mass(const LocalState& s, MatX& M) const override { return inner_->mass(s, M); }
  void force(const LocalState& s, VecX& Q) const override { inner_->force(s, Q); }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override {
    ++calls_;
    inner_->forceJacobian(s, dQdq, dQdv);
  }
  bool velocityDependent() const override { return declareDamped_ || inner_->velocityDependent(); }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override {
    return inner_->parameterDerivative(s, k, dQ, dM);
  }
  bool isLoad() const override { return inner_->isLoad(); }
  bool externalWork() const override { return inner_->externalWork(); }
  double potential(const LocalState& s) const override { return inner_->potential(s); }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return inner_->properties(); }

 private:
  std::unique_ptr<Element> inner_;
  bool declareDamped_;
  long& calls_;
};

std::string pendulumText() {
  std::ifstream in(sourceDir() + "/examples/solid/pendulum3d.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("size: 0.04"), 10, "size: 0.08");  // coarser: a short test
  return text;
}

struct CountedRun {
  Recorder frames;
  long jacobianCalls = 0;
  size_t elements = 0;
};

/// The coarsened pendulum with its two parameters (E, density), 10 steps of 5 ms.
CountedRun runPendulum(bool declareDamped) {
  CountedRun r;
  const Scene sc = readSceneText(pendulumText(), sourceDir() + "/examples/solid/pendulum3d.yaml");
  Model& m = *sc.model;
  for (auto& el : m.elements) {
    EXPECT_FALSE(el->velocityDependent()) << el->name() << ": undamped";
    el = std::make_unique<CountingElement>(std::move(el), declareDamped, r.jacobianCalls);
  }
  r.elements = m.elements.size();
  Assembler as(m);
  const VecX p = m.nominalParameters();
  auto set = integratorSettings("trapezoidal", 0.005, 0.05);
  set.frameInterval = 0.005;
  integrate(as, p, initialState(as, p), set, r.frames);
  return r;
}

/// Max |a - b| over the frames' q and dq/dp, relative to the largest |b|.
double seriesDifference(const Recorder& a, const Recorder& b) {
  double diff = 0.0, scale = 0.0;
  for (size_t f = 0; f < b.frames.size(); ++f) {
    diff = std::max(diff, (a.frames[f].x.q - b.frames[f].x.q).lpNorm<Eigen::Infinity>());
    scale = std::max(scale, b.frames[f].x.q.lpNorm<Eigen::Infinity>());
    for (size_t k = 0; k < b.frames[f].dp.size(); ++k) {
      diff = std::max(diff, (a.frames[f].dp[k].q - b.frames[f].dp[k].q).lpNorm<Eigen::Infinity>());
      scale = std::max(scale, b.frames[f].dp[k].q.lpNorm<Eigen::Infinity>());
    }
  }
  return diff / scale;
}

/// dQ/dv by AD at a moving state: exactly zero when e declares velocity independence.
void expectDeclarationHolds(const Element& e, const LocalState& s, bool damped) {
  SCOPED_TRACE(e.kind() + (damped ? " damped" : " undamped"));
  MatX Kq, Kv;
  e.forceJacobianAD(s, Kq, Kv);
  EXPECT_EQ(e.velocityDependent(), damped);
  if (damped) EXPECT_GT(Kv.norm(), 0.0);
  else EXPECT_EQ(Kv.norm(), 0.0);
}

LocalState movingState(const VecX& x, const VecX* p) {
  LocalState s;
  s.dim = 3;
  s.x = x;
  std::srand(23);
  s.v = VecX::Random(x.size());
  s.p = p;
  return s;
}

}  // namespace

TEST(UndampedSensitivity, MeshedElementsDeclareVelocityIndependenceExactlyWhenUndamped) {
  const VecX p = (VecX(1) << 0.0).finished();  // a damping bound to parameter 0, at value 0
  auto tet = std::make_shared<SolidProperties>();
  tet->dim = 3;
  tet->E = {2.0e6, -1};
  tet->nu = {0.3, -1};
  tet->density = {1000.0, -1};
  tet->law = {Law::NeoHookean, PlanarState::None};
  MatX X(3, 4);
  X << 0.0, 1.0, 0.1, 0.2, 0.0, 0.1, 0.9, 0.1, 0.0, 0.1, 0.2, 1.1;
  const VecX x = Eigen::Map<const VecX>(X.data(), 12);
  const Solid solid("s", {0, 1, 2, 3}, tet, Simplex::Tet4, X);
  expectDeclarationHolds(solid, movingState(x, &p), false);
  for (Quantity* damping : {&tet->alpha, &tet->beta}) {
    *damping = {0.2, -1};
    expectDeclarationHolds(solid, movingState(x, &p), true);
    *damping = {0.0, 0};  // bound to a parameter: may be nonzero at another p
    EXPECT_TRUE(solid.velocityDependent());
    *damping = {0.0, -1};
  }
  auto shell = std::make_shared<ShellProperties>();
  shell->E = {4.0e9, -1};
  shell->nu = {0.38, -1};
  shell->density = {1380.0, -1};
  shell->thickness = {5e-4, -1};
  const ShellTriangle tri("t", {0, 1, 2}, shell, x.head(9));
  const ShellHinge hinge("h", {0, 1, 2, 3}, shell, x);
  const ShellClampHinge clamp("c", {0, 1, 2}, shell, x.head(9));
  for (const Element* e : std::initializer_list<const Element*>{&tri, &hinge, &clamp})
    expectDeclarationHolds(*e, movingState(x.head(e->nodes().size() * 3), &p), false);
  shell->alpha = {0.5, -1};  // the membrane's mass damping; the hinges have none
  expectDeclarationHolds(tri, movingState(x.head(9), &p), true);
  expectDeclarationHolds(hinge, movingState(x, &p), false);
  shell->beta = {0.01, -1};  // Kelvin-Voigt: membrane and bending
  for (const Element* e : std::initializer_list<const Element*>{&tri, &hinge, &clamp})
    expectDeclarationHolds(*e, movingState(x.head(e->nodes().size() * 3), &p), true);
}

TEST(UndampedSensitivity, SolidPendulumSkipsTheVelocityJacobianPassWithTheSameSeries) {
  const CountedRun declared = runPendulum(false), asBefore = runPendulum(true);
  ASSERT_EQ(declared.frames.frames.size(), asBefore.frames.frames.size());
  ASSERT_EQ(declared.frames.frames.size(), 11u);
  ASSERT_EQ(declared.frames.frames.back().dp.size(), 2u);  // dq/dE, dq/ddensity
  const double diff = seriesDifference(declared.frames, asBefore.frames);
  std::printf("  pendulum3d coarse: %zu elements, force-Jacobian calls %ld (declared) vs %ld (all velocity-"
              "dependent); series differ by %.1e\n",
              declared.elements, declared.jacobianCalls, asBefore.jacobianCalls, diff);
  EXPECT_LE(diff, 1e-13);
  // The dQ/dv pass calls every element once; the undamped run makes none of them: at least one
  // pass per step (10 steps), and the same count of every other call.
  const long extra = asBefore.jacobianCalls - declared.jacobianCalls;
  EXPECT_EQ(extra % long(declared.elements), 0);
  EXPECT_GE(extra / long(declared.elements), 10);
}
