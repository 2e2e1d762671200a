// The fluid state on the MAC grid: face velocities and the kinematic pressure
// (p / rho) of the last projection.
#pragma once
#include "../src/grid.hpp"

namespace softflow {

struct FlowState {
  Field3 u, v, w, p;
  FlowState() = default;
  explicit FlowState(const Grid& g)
      : u("u", g.sx(), g.sy(), g.sz()),
        v("v", g.sx(), g.sy(), g.sz()),
        w("w", g.sx(), g.sy(), g.sz()),
        p("p", g.sx(), g.sy(), g.sz()) {}
};

// Right-hand side of the momentum equation, one array per component.
struct MomentumRhs {
  Field3 u, v, w;
  MomentumRhs() = default;
  MomentumRhs(const Grid& g, const char* label)
      : u(std::string(label) + "_u", g.sx(), g.sy(), g.sz()),
        v(std::string(label) + "_v", g.sx(), g.sy(), g.sz()),
        w(std::string(label) + "_w", g.sx(), g.sy(), g.sz()) {}
};

}  // namespace softflow
