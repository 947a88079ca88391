// Crocoddyl anchor for corps' human path prediction (issue 25, Deliver 4).
//
// The human walking OCP of crates/corps-ocp/src/human_walk.rs (Maroger et al.; seed 000
// §3.17) written a third time (after tools/golden/human_walk_crocoddyl.py), as C++ action
// models, so that crocoddyl::SolverDDP is timed, not Python callbacks. State
// (x, y, θ, v_f, ω, v_o), controls the three accelerations, one explicit step of dt = 0.1 s;
// running cost w0 + w1 u_f² + w2 u_ω² + w3 u_o² + w4 (atan2(y_g − y, x_g − x) − θ)² (no
// wrapping, as the source), terminal cost t0 |p_g − p|² + t1 wrap(θ_g − θ)² + t2 (v_f² + ω²)
// + t3 v_o²; the same analytic derivatives, in the same order of operations, as corps.
//
// Input: the problems file corps' bench writes (crates/corps-ocp/benches/human_walk.rs),
//   ddp <name> <nodes> <x0: 6> <goal: 3> <corps iterations> <corps cost>
//   predict <name> <x0: 6> <goal: 3> <corps nodes> <corps cost> <corps solves> <horizons...>
// "ddp": one solve from zero controls (their rollout as the initial guess, feasible), th_stop
// 1e-9 (Crocoddyl's default and corps' DdpSettings::default), at most 200 iterations.
// "predict": one prediction, i.e. the horizons corps' search solved (listed in the file),
// each a new problem solved from scratch as above; beside it, the predictor's horizon search
// (crates/corps-ocp/src/prediction.rs: golden section over the integers in [guess/3, 3 guess],
// then a scan) run on Crocoddyl's own solves, which takes another path when the two solvers'
// unconverged solves score differently (long horizons neither solver converges on).
//
// Stopping: Crocoddyl 3's SolverDDP stops on the expected improvement |d₀ + ½d₁| < th_stop;
// corps (DdpSettings) on Σ‖Q_u‖² < th_stop, as Crocoddyl 1.x did. Both are timed: the stock
// solver, and SolverDDPGradient below (SolverDDP with corps' criterion, "gradient_*").
//
// Output, one line per problem (times per solve or prediction, µs, over `reps` repetitions
// after a warmup; median and min):
//   ddp <name> nodes= iterations= gradient_iterations= corps_iterations= converged=
//       gradient_converged= cost= gradient_cost= corps_cost= rel_diff= gradient_rel_diff=
//       median_us= min_us= solve_median_us= solve_min_us= gradient_median_us= gradient_min_us=
//       reps=
// median_us/min_us: ShootingProblem + SolverDDP built and solved (what a new horizon costs,
// and what corps' Ddp::solve does); solve_*: the stock solver built once, only solve() timed.
//   predict <name> horizons= corps_nodes= converged_at_corps_nodes= cost_at_corps_nodes=
//       corps_cost= rel_diff= iterations= gradient_iterations= median_us= min_us=
//       gradient_median_us= gradient_min_us= (corps' horizons, iterations summed over them)
//       own_search_nodes= own_search_solves= own_search_converged= own_search_median_us=
//       own_search_min_us= gradient_own_search_nodes= gradient_own_search_solves= reps=
//
// Usage: human_walk_croc_bench <problems file> [reps (default 300)]
// Build: tools/anchors/run_human_walk_bench.sh (g++ -O3 -DNDEBUG against the PyPI wheel).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <crocoddyl/core/action-base.hpp>
#include <crocoddyl/core/optctrl/shooting.hpp>
#include <crocoddyl/core/solvers/ddp.hpp>
#include <crocoddyl/core/states/euclidean.hpp>

using crocoddyl::ActionDataAbstract;
using crocoddyl::ActionModelAbstract;
using Eigen::VectorXd;
typedef Eigen::Ref<const VectorXd> RefX;

// Crocoddyl 3's scalar casts (pure virtual in ActionModelBase): double only, unused here.
#define DOUBLE_ONLY(T)                                                           \
  std::shared_ptr<crocoddyl::ActionModelBase> cloneAsDouble() const override { \
    return std::make_shared<T>(*this);                                           \
  }                                                                              \
  std::shared_ptr<crocoddyl::ActionModelBase> cloneAsFloat() const override {  \
    throw std::logic_error(#T " is double only");                                \
  }

// corps-ocp/src/human_walk.rs: RUNNING_WEIGHTS, TERMINAL_WEIGHTS, DT.
static const double W[5] = {7.86951486, 4.00027971, 20.1459991, 1e-6, 9.99999967};
static const double T[4] = {9.98999939, 9.98999934, 0.379999984, 3.35999389};
static const double DT = 0.1;

// One step towards goal (x_g, y_g, θ_g): HumanWalkStep.
class Step : public ActionModelAbstract {
 public:
  explicit Step(const double goal[3])
      : ActionModelAbstract(std::make_shared<crocoddyl::StateVector>(6), 3) {
    for (int i = 0; i < 3; ++i) goal_[i] = goal[i];
  }
  DOUBLE_ONLY(Step)

  // h = atan2(y_g − y, x_g − x) − θ, its gradient and Hessian in (x, y, θ) (HumanWalkStep::heading).
  void heading(const RefX& x, double& h, double g[3], double hh[3][3]) const {
    const double dx = goal_[0] - x[0], dy = goal_[1] - x[1];
    const double r2 = std::max(dx * dx + dy * dy, 1e-12);
    const double r4 = r2 * r2;
    h = std::atan2(dy, dx) - x[2];
    g[0] = dy / r2;
    g[1] = -dx / r2;
    g[2] = -1.0;
    const double hxx = 2.0 * dx * dy / r4, hxy = (dy * dy - dx * dx) / r4;
    const double m[3][3] = {{hxx, hxy, 0.0}, {hxy, -hxx, 0.0}, {0.0, 0.0, 0.0}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) hh[i][j] = m[i][j];
  }

  void calc(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x, const RefX& u) override {
    const double c = std::cos(x[2]), s = std::sin(x[2]), dt = DT;
    d->xnext[0] = x[0] + (c * x[3] - s * x[5]) * dt;
    d->xnext[1] = x[1] + (s * x[3] + c * x[5]) * dt;
    d->xnext[2] = x[2] + x[4] * dt;
    d->xnext[3] = x[3] + u[0] * dt;
    d->xnext[4] = x[4] + u[1] * dt;
    d->xnext[5] = x[5] + u[2] * dt;
    double h, g[3], hh[3][3];
    heading(x, h, g, hh);
    d->cost = W[0] + W[1] * u[0] * u[0] + W[2] * u[1] * u[1] + W[3] * u[2] * u[2] + W[4] * h * h;
  }

  void calc(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x) override {
    calc(d, x, VectorXd::Zero(3));
  }

  void calcDiff(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x,
                const RefX& u) override {
    const double c = std::cos(x[2]), s = std::sin(x[2]), dt = DT;
    d->Fx.setIdentity();
    d->Fx(0, 2) = (-s * x[3] - c * x[5]) * dt;
    d->Fx(0, 3) = c * dt;
    d->Fx(0, 5) = -s * dt;
    d->Fx(1, 2) = (c * x[3] - s * x[5]) * dt;
    d->Fx(1, 3) = s * dt;
    d->Fx(1, 5) = c * dt;
    d->Fx(2, 4) = dt;
    d->Fu.setZero();
    for (int i = 0; i < 3; ++i) d->Fu(3 + i, i) = dt;
    double h, g[3], hh[3][3];
    heading(x, h, g, hh);
    d->Lx.setZero();
    d->Lxx.setZero();
    for (int i = 0; i < 3; ++i) {
      d->Lx[i] = 2.0 * W[4] * h * g[i];
      for (int j = 0; j < 3; ++j) d->Lxx(i, j) = 2.0 * W[4] * (g[i] * g[j] + h * hh[i][j]);
    }
    for (int i = 0; i < 3; ++i) d->Lu[i] = 2.0 * W[1 + i] * u[i];
    d->Luu.setZero();
    for (int i = 0; i < 3; ++i) d->Luu(i, i) = 2.0 * W[1 + i];
    d->Lxu.setZero();
  }

  void calcDiff(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x) override {
    calcDiff(d, x, VectorXd::Zero(3));
  }

 private:
  double goal_[3];
};

// wrap_angle: into [−π, π].
static double wrap(double a) {
  while (a > M_PI) a -= 2.0 * M_PI;
  while (a < -M_PI) a += 2.0 * M_PI;
  return a;
}

// The terminal cost towards goal: HumanWalkEnd.
class End : public ActionModelAbstract {
 public:
  explicit End(const double goal[3])
      : ActionModelAbstract(std::make_shared<crocoddyl::StateVector>(6), 3) {
    for (int i = 0; i < 3; ++i) g_[i] = goal[i];
  }
  DOUBLE_ONLY(End)

  void calc(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x) override {
    const double dth = wrap(g_[2] - x[2]);
    d->xnext = x;
    d->cost = T[0] * ((g_[0] - x[0]) * (g_[0] - x[0]) + (g_[1] - x[1]) * (g_[1] - x[1])) +
              T[1] * dth * dth + T[2] * (x[3] * x[3] + x[4] * x[4]) + T[3] * x[5] * x[5];
  }
  void calc(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x, const RefX&) override {
    calc(d, x);
  }

  void calcDiff(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x) override {
    const double dth = wrap(g_[2] - x[2]);
    d->Lx.setZero();
    d->Lxx.setZero();
    d->Lx[0] = -2.0 * T[0] * (g_[0] - x[0]);
    d->Lx[1] = -2.0 * T[0] * (g_[1] - x[1]);
    d->Lx[2] = -2.0 * T[1] * dth;
    d->Lx[3] = 2.0 * T[2] * x[3];
    d->Lx[4] = 2.0 * T[2] * x[4];
    d->Lx[5] = 2.0 * T[3] * x[5];
    const double w[6] = {T[0], T[0], T[1], T[2], T[2], T[3]};
    for (int i = 0; i < 6; ++i) d->Lxx(i, i) = 2.0 * w[i];
  }
  void calcDiff(const std::shared_ptr<ActionDataAbstract>& d, const RefX& x,
                const RefX&) override {
    calcDiff(d, x);
  }

 private:
  double g_[3];
};

static const std::size_t MAX_ITERATIONS = 200;  // DdpSettings::default()
static const double TH_STOP = 1e-9;             // idem, Crocoddyl's default

// SolverDDP stopping on Σ_k ‖Q_u‖² < th_stop, corps' criterion (and Crocoddyl 1.x's), instead
// of Crocoddyl 3's expected improvement |d₀ + ½d₁| (crocoddyl/src/core/solvers/ddp.cpp,
// stoppingCriteria); the algorithm is otherwise SolverDDP's.
class SolverDDPGradient : public crocoddyl::SolverDDP {
 public:
  using crocoddyl::SolverDDP::SolverDDP;
  double stoppingCriteria() override {
    stop_ = 0.;
    for (const auto& qu : Qu_) stop_ += qu.squaredNorm();
    return stop_;
  }
};

enum Criterion { STOCK, GRADIENT };

struct Result {
  bool converged;
  std::size_t iterations;
  double cost;
};

// One OCP: the problem, its solver and the initial guess (zero controls and their rollout).
struct Ocp {
  std::shared_ptr<crocoddyl::ShootingProblem> problem;
  std::shared_ptr<crocoddyl::SolverDDP> ddp;
  std::vector<VectorXd> xs, us;

  Ocp(const VectorXd& x0, const double goal[3], std::size_t nodes, Criterion c) {
    auto step = std::make_shared<Step>(goal);
    auto end = std::make_shared<End>(goal);
    std::vector<std::shared_ptr<ActionModelAbstract> > running(nodes, step);
    problem = std::make_shared<crocoddyl::ShootingProblem>(x0, running, end);
    problem->set_nthreads(1);  // corps is single-threaded; so is this comparison
    if (c == STOCK)
      ddp = std::make_shared<crocoddyl::SolverDDP>(problem);
    else
      ddp = std::make_shared<SolverDDPGradient>(problem);
    ddp->set_th_stop(TH_STOP);
    us.assign(nodes, VectorXd::Zero(3));
    xs.assign(nodes + 1, x0);
    problem->rollout(us, xs);
  }

  Result solve() {
    const bool converged = ddp->solve(xs, us, MAX_ITERATIONS, true);
    return Result{converged, ddp->get_iter(), ddp->get_cost()};
  }
};

static Result solve_once(const VectorXd& x0, const double goal[3], std::size_t nodes,
                         Criterion c) {
  Ocp ocp(x0, goal, nodes, c);
  return ocp.solve();
}

struct Predicted {
  std::size_t nodes, solves;
  double cost;
  bool converged;
};

// prediction.rs `predict` from its start state x0 (the state estimate is corps', in the
// problems file): the horizon minimising the authors' score, by the same search.
static Predicted predict(const VectorXd& x0, const double goal[3], Criterion c) {
  std::map<std::size_t, std::pair<double, Result> > solved;
  auto score = [&](std::size_t nodes) {
    auto it = solved.find(nodes);
    if (it != solved.end()) return it->second.first;
    const Result r = solve_once(x0, goal, nodes, c);
    const double per_node = r.cost / double(nodes);
    const double s = r.converged ? per_node : (r.iterations < 50 ? 10.0 * per_node : 1e4);
    solved[nodes] = std::make_pair(s, r);
    if (std::getenv("HUMAN_WALK_VERBOSE"))
      std::fprintf(stderr, "  horizon %zu: %zu iterations, converged %d, cost %.12g, score %.6g\n",
                   nodes, r.iterations, int(r.converged), r.cost, s);
    return s;
  };
  const double distance = std::hypot(goal[0] - x0[0], goal[1] - x0[1]);
  const std::size_t guess =
      std::max<std::size_t>(std::size_t(std::ceil(distance / 1.0 / DT)), 2);  // GUESS_SPEED 1 m/s
  std::size_t lo = std::max<std::size_t>(guess / 3, 2), hi = 3 * guess;
  while (hi - lo > 2) {
    const double third = double(hi - lo) * 0.381966;
    const std::size_t r = std::size_t(std::round(third));
    std::size_t a = lo + r, b = hi - r;
    const std::size_t a2 = std::max(std::min(a, b > 0 ? b - 1 : 0), lo);
    const std::size_t b2 = std::min(std::max(b, a + 1), hi);
    a = a2;
    b = b2;
    if (score(a) <= score(b)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  std::size_t best = lo;
  for (std::size_t n = lo; n <= hi; ++n)
    if (score(n) < score(best)) best = n;
  const Result& r = solved[best].second;
  return Predicted{best, solved.size(), r.cost, r.converged};
}

template <class F>
static std::pair<double, double> time_us(F f, int reps) {
  const int warmup = std::max(10, reps / 10);
  for (int i = 0; i < warmup; ++i) f();
  std::vector<double> t(reps);
  for (int i = 0; i < reps; ++i) {
    const auto a = std::chrono::steady_clock::now();
    f();
    const auto b = std::chrono::steady_clock::now();
    t[i] = std::chrono::duration<double, std::micro>(b - a).count();
  }
  std::sort(t.begin(), t.end());
  const double median = reps % 2 ? t[reps / 2] : 0.5 * (t[reps / 2 - 1] + t[reps / 2]);
  return std::make_pair(median, t[0]);
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <problems file> [reps]\n", argv[0]);
    return 2;
  }
  const int reps = argc > 2 ? std::atoi(argv[2]) : 300;
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  std::printf("# crocoddyl %s SolverDDP, th_stop %g, max %zu iterations, 1 thread\n",
              CROCODDYL_VERSION, TH_STOP, MAX_ITERATIONS);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string kind, name;
    if (!(ss >> kind >> name)) continue;
    std::size_t nodes = 0;
    if (kind == "ddp") ss >> nodes;
    VectorXd x0(6);
    double goal[3];
    for (int i = 0; i < 6; ++i) ss >> x0[i];
    for (int i = 0; i < 3; ++i) ss >> goal[i];
    if (kind == "ddp") {
      std::size_t corps_iterations;
      double corps_cost;
      ss >> corps_iterations >> corps_cost;
      if (!ss) {
        std::fprintf(stderr, "bad line: %s\n", line.c_str());
        return 1;
      }
      const Result r = solve_once(x0, goal, nodes, STOCK);
      const Result g = solve_once(x0, goal, nodes, GRADIENT);
      const auto full = time_us([&] { solve_once(x0, goal, nodes, STOCK); }, reps);
      Ocp ocp(x0, goal, nodes, STOCK);
      const auto only = time_us([&] { ocp.solve(); }, reps);
      const auto full_g = time_us([&] { solve_once(x0, goal, nodes, GRADIENT); }, reps);
      std::printf(
          "ddp %s nodes=%zu iterations=%zu gradient_iterations=%zu corps_iterations=%zu "
          "converged=%d gradient_converged=%d cost=%.15g gradient_cost=%.15g corps_cost=%.15g "
          "rel_diff=%.2e gradient_rel_diff=%.2e median_us=%.2f min_us=%.2f "
          "solve_median_us=%.2f solve_min_us=%.2f gradient_median_us=%.2f "
          "gradient_min_us=%.2f reps=%d\n",
          name.c_str(), nodes, r.iterations, g.iterations, corps_iterations, int(r.converged),
          int(g.converged), r.cost, g.cost, corps_cost,
          std::abs(r.cost - corps_cost) / std::abs(corps_cost),
          std::abs(g.cost - corps_cost) / std::abs(corps_cost), full.first, full.second,
          only.first, only.second, full_g.first, full_g.second, reps);
    } else if (kind == "predict") {
      std::size_t corps_nodes, corps_solves, h;
      double corps_cost;
      ss >> corps_nodes >> corps_cost >> corps_solves;
      std::vector<std::size_t> horizons;
      while (ss >> h) horizons.push_back(h);
      if (horizons.size() != corps_solves || corps_solves == 0) {
        std::fprintf(stderr, "bad line: %s\n", line.c_str());
        return 1;
      }
      // The horizons corps' search solved, each solved by Crocoddyl from scratch.
      auto same = [&](Criterion c) {
        return time_us(
            [&] {
              for (std::size_t n : horizons) solve_once(x0, goal, n, c);
            },
            reps);
      };
      const auto stock = same(STOCK), gradient = same(GRADIENT);
      std::size_t iterations = 0, gradient_iterations = 0;
      for (std::size_t n : horizons) {
        iterations += solve_once(x0, goal, n, STOCK).iterations;
        gradient_iterations += solve_once(x0, goal, n, GRADIENT).iterations;
      }
      const Result at = solve_once(x0, goal, corps_nodes, STOCK);
      // Crocoddyl's own search (it may take another path where solves fail to converge).
      const Predicted p = predict(x0, goal, STOCK), pg = predict(x0, goal, GRADIENT);
      const auto own = time_us([&] { predict(x0, goal, STOCK); }, reps);
      std::printf(
          "predict %s horizons=%zu corps_nodes=%zu converged_at_corps_nodes=%d "
          "cost_at_corps_nodes=%.15g corps_cost=%.15g rel_diff=%.2e iterations=%zu "
          "gradient_iterations=%zu median_us=%.2f min_us=%.2f gradient_median_us=%.2f "
          "gradient_min_us=%.2f own_search_nodes=%zu own_search_solves=%zu "
          "own_search_converged=%d own_search_median_us=%.2f own_search_min_us=%.2f "
          "gradient_own_search_nodes=%zu gradient_own_search_solves=%zu reps=%d\n",
          name.c_str(), horizons.size(), corps_nodes, int(at.converged), at.cost, corps_cost,
          std::abs(at.cost - corps_cost) / std::abs(corps_cost), iterations,
          gradient_iterations, stock.first, stock.second, gradient.first, gradient.second,
          p.nodes, p.solves, int(p.converged), own.first, own.second, pg.nodes, pg.solves,
          reps);
    }
    std::fflush(stdout);
  }
  return 0;
}
