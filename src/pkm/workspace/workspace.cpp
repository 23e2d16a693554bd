// The octree refinement of the reachable workspace (workspace.hpp; the argument is in
// docs/workspace.md).
#include "pkm/workspace/workspace.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/workspace/inscribed.hpp"
#include "pkm/workspace/plane_maps.hpp"
#include "pkm/workspace/pose_constraints.hpp"

namespace pkm::workspace {

WorkspaceOptions default_options(const machine::Machine& machine) {
  WorkspaceOptions options;
  options.orientation_min_rad = machine.home().orientation_rad;
  options.orientation_max_rad = machine.home().orientation_rad;
  return options;
}

namespace {

// Every position: the box the search starts from before the machine's limits cut it.
Eigen::AlignedBox3d everywhere() {
  return {Eigen::Vector3d::Constant(-INFINITY), Eigen::Vector3d::Constant(INFINITY)};
}

// Pass-through joints copy their axis: its range is the joint's.
void cut_by_passthrough(const machine::Machine& machine, Eigen::AlignedBox3d& box) {
  const kinematics::Kinematics& model = machine.kinematics();
  for (int joint = 0; joint < model.joint_count(); ++joint) {
    const int axis = model.passthrough_axis(joint);
    if (axis < 0 || axis >= 3) continue;
    const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
    box.min()[axis] = std::max(box.min()[axis], spec.min);
    box.max()[axis] = std::min(box.max()[axis], spec.max);
  }
}

}  // namespace

SearchBox search_box(const machine::Machine& machine, const WorkspaceOptions& /*options*/) {
  const kinematics::Kinematics& model = machine.kinematics();
  SearchBox result{everywhere(), true};
  Eigen::AlignedBox3d& box = result.box;
  const auto joints = static_cast<Eigen::Index>(machine.joints().size());
  kinematics::JointVector joint_min(joints), joint_max(joints);
  for (Eigen::Index j = 0; j < joints; ++j) {
    joint_min[j] = machine.joints()[static_cast<std::size_t>(j)].min;
    joint_max[j] = machine.joints()[static_cast<std::size_t>(j)].max;
  }
  if (const auto reach = model.tool_position_box(joint_min, joint_max)) box = *reach;
  cut_by_passthrough(machine, box);
  const machine::CartesianLimits& limits = machine.cartesian();
  for (int axis = 0; axis < 3; ++axis) {
    box.min()[axis] = std::max(box.min()[axis], limits.envelope_min[axis]);
    box.max()[axis] = std::min(box.max()[axis], limits.envelope_max[axis]);
  }
  // What is still open: the extent along lines through home, widened by half on each side.
  const std::vector<machine::AxisExtent> extent = machine::reachable_extent(machine);
  for (const machine::AxisExtent& line : extent) {
    if (line.axis >= 3) continue;
    if (std::isfinite(box.min()[line.axis]) && std::isfinite(box.max()[line.axis])) continue;
    const double widen = 0.5 * (line.max - line.min) + 1.0;
    if (!std::isfinite(box.min()[line.axis])) box.min()[line.axis] = line.min - widen;
    if (!std::isfinite(box.max()[line.axis])) box.max()[line.axis] = line.max + widen;
    result.proven = false;
  }
  return result;
}

namespace {

// A box of orientations (rad): centre +- half on a b c.
struct OrientationBox {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  // Constraint values proven over this box and a position cell holding the current one.
  std::uint64_t settled = 0;
};

enum class Verdict { inside, outside, undecided };

// One top cell's constraints (with their scratch) and findings; the machine is shared by every
// thread, constant (a model's per-call scratch is its own per thread: docs/kinematics.md).
struct Worker {
  explicit Worker(const machine::Machine& shared) : machine(shared) {
    constraints = machine_constraints(machine);
    int total = 0;
    for (const auto& constraint : constraints) total += constraint->count();
    margins.resize(static_cast<std::size_t>(total));
  }
  const machine::Machine& machine;
  std::vector<std::unique_ptr<PoseConstraint>> constraints;
  std::vector<Margin> margins;
  std::vector<CellIndex> inside, boundary;
  std::map<std::string, std::int64_t> limited_by;
  std::int64_t judged = 0;
  std::int64_t poses_judged = 0;
  std::int64_t unbounded_refusals = 0;  // cells proven inside whose middle inverse() refused
  int dimensions = 0;
};

// The grid, shared read-only by the workers.
struct Grid {
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();
  double step_mm = 1.0;
  std::array<bool, 3> spans{};
  Eigen::Vector3d fixed = Eigen::Vector3d::Zero();  // the coordinates of axes not spanned
  double angle_scale_mm = 100.0;
  OrientationBox range;  // the whole orientation range
  std::atomic<std::int64_t>* judged = nullptr;
  std::int64_t max_cells = 0;
};

// `settled`: the constraint values (bit per value, in the order of worker.margins) proven over a
// cell holding this one; those proven here are added to it. `splits_orientation`, when given, is
// set if an undecided value's constraint would be tighter over a smaller orientation box (one
// that does not search the box itself).
Verdict judge(Worker& worker, const PoseCell& cell, kinematics::Status& why,
              std::uint64_t* settled = nullptr, bool* splits_orientation = nullptr) {
  ++worker.poses_judged;
  Verdict verdict = Verdict::inside;
  std::size_t offset = 0;
  const std::uint64_t known = settled != nullptr ? *settled : 0;
  for (const auto& constraint : worker.constraints) {
    const std::span<Margin> margins(worker.margins.data() + offset,
                                    static_cast<std::size_t>(constraint->count()));
    const std::uint64_t mine = offset < 64 ? known >> offset : 0;
    constraint->bound(cell, margins, mine);
    const bool closed = constraint->closed();
    for (std::size_t k = 0; k < margins.size(); ++k) {
      const std::size_t bit = offset + k;
      if (bit < 64 && ((known >> bit) & 1u)) continue;
      if (margins[k].high < 0.0) {
        why = constraint->failure(static_cast<int>(k));
        return Verdict::outside;
      }
      if (margins[k].low > 0.0 || (closed && margins[k].low >= 0.0)) {
        if (settled != nullptr && bit < 64) *settled |= std::uint64_t{1} << bit;
      } else {
        if (splits_orientation != nullptr && !constraint->covers_orientation())
          *splits_orientation = true;
        if (verdict == Verdict::inside) {
          verdict = Verdict::undecided;
          why = constraint->failure(static_cast<int>(k));
        }
      }
    }
    offset += margins.size();
  }
  return verdict;
}

PoseCell position_cell(const Grid& grid, const CellIndex& cell) {
  PoseCell pose;
  const double side = grid.step_mm * std::ldexp(1.0, cell.level);
  for (int axis = 0; axis < 3; ++axis) {
    if (grid.spans[static_cast<std::size_t>(axis)]) {
      pose.centre[axis] = grid.origin_mm[axis] +
                          grid.step_mm * cell.at[static_cast<std::size_t>(axis)] + 0.5 * side;
      pose.half[axis] = 0.5 * side;
    } else {
      pose.centre[axis] = grid.fixed[axis];
    }
  }
  return pose;
}

// The undecided orientation boxes of a position cell, split while they are wider (scaled) than
// the cell; `outside` set (with why) when some orientation fails for every point of the cell.
struct Settling {
  std::vector<OrientationBox> open;
  bool outside = false;
  kinematics::Status why;
};

void settle(Worker& worker, const Grid& grid, PoseCell cell, OrientationBox box,
            Settling& settling) {
  cell.centre.tail<3>() = box.centre;
  cell.half.tail<3>() = box.half;
  kinematics::Status why;
  bool splits_orientation = false;
  const Verdict verdict = judge(worker, cell, why, &box.settled, &splits_orientation);
  if (verdict == Verdict::inside) return;
  if (verdict == Verdict::outside) {
    settling.outside = true;
    settling.why = why;
    return;
  }
  // Undecided: split while the box is wider (scaled) than the position cell, whose own size
  // bounds what a finer box can settle.
  const double position_radius = cell.half.head<3>().norm();
  const double angle_radius = grid.angle_scale_mm * box.half.norm();
  if (splits_orientation && angle_radius > position_radius) {
    std::array<int, 3> spread{};
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      if (box.half[k] > 0.0) spread[static_cast<std::size_t>(n++)] = k;
    }
    for (unsigned part = 0; part < (1u << n) && !settling.outside; ++part) {
      OrientationBox piece = box;
      for (int k = 0; k < n; ++k) {
        const int axis = spread[static_cast<std::size_t>(k)];
        piece.half[axis] = 0.5 * box.half[axis];
        piece.centre[axis] += ((part >> k) & 1u) ? piece.half[axis] : -piece.half[axis];
      }
      settle(worker, grid, cell, piece, settling);
    }
    return;
  }
  // At the box's middle orientation alone, does every point of the cell fail?
  if (box.half.squaredNorm() > 0.0) {
    PoseCell point = cell;
    point.half.tail<3>().setZero();
    kinematics::Status middle_why;
    if (judge(worker, point, middle_why) == Verdict::outside) {
      settling.outside = true;
      settling.why = middle_why;
      return;
    }
  }
  settling.open.push_back(box);
  settling.why = why;
}

// The share of the cell's quarter points (each coordinate at +-1/4 of its side: the midpoint
// rule on its sub-cells) where Machine::inverse accepts the range's middle and corners.
double reachable_share(const machine::Machine& machine, const PoseCell& cell,
                       const OrientationBox& range) {
  kinematics::JointVector joints;
  std::array<int, 3> spread{};
  int n = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (cell.half[axis] > 0.0) spread[static_cast<std::size_t>(n++)] = axis;
  }
  int reached = 0;
  for (unsigned point = 0; point < (1u << n); ++point) {
    geometry::Vector6d position = cell.centre;
    for (int k = 0; k < n; ++k) {
      const int axis = spread[static_cast<std::size_t>(k)];
      position[axis] += ((point >> k) & 1u) ? 0.5 * cell.half[axis] : -0.5 * cell.half[axis];
    }
    bool all = true;
    for (unsigned corner = 0; corner <= 8 && all; ++corner) {
      geometry::Vector6d pose = position;
      pose.tail<3>() = range.centre;
      if (corner < 8) {
        for (int k = 0; k < 3; ++k)
          pose[3 + k] += ((corner >> k) & 1u) ? range.half[k] : -range.half[k];
      }
      all = machine.inverse(geometry::Pose::from_vector(pose), joints).ok();
      if (range.half.squaredNorm() == 0.0) break;
    }
    reached += all ? 1 : 0;
  }
  return static_cast<double>(reached) / (1u << n);
}

void refine_children(Worker& worker, const Grid& grid, const CellIndex& cell,
                     const std::vector<OrientationBox>& open);

void refine(Worker& worker, const Grid& grid, const CellIndex& cell,
            const std::vector<OrientationBox>& open) {
  ++worker.judged;
  if (grid.judged->fetch_add(1, std::memory_order_relaxed) > grid.max_cells) {
    throw std::invalid_argument("more than " + std::to_string(grid.max_cells) +
                                " cells to judge: choose a coarser --resolution");
  }
  const PoseCell base = position_cell(grid, cell);
  Settling settling;
  for (const OrientationBox& box : open) {
    settle(worker, grid, base, box, settling);
    if (settling.outside) {
      ++worker.limited_by[std::string(kinematics::status_identifier(settling.why.code))];
      return;
    }
  }
  if (settling.open.empty()) {
    // A check on the bounds, not part of the proof: Machine::inverse must accept the cell's
    // middle. A refusal there means it applies a limit no constraint bounds (a new per-pose
    // limit of a model): the cell is not claimed, and the result says so.
    kinematics::JointVector joints;
    PoseCell middle = base;
    middle.centre.tail<3>() = grid.range.centre;
    const kinematics::Status status =
        worker.machine.inverse(geometry::Pose::from_vector(middle.centre), joints);
    if (!status.ok()) {
      ++worker.unbounded_refusals;
      ++worker.limited_by[std::string(kinematics::status_identifier(status.code))];
      if (cell.level > 0) {
        refine_children(worker, grid, cell, open);
      } else {
        worker.boundary.push_back(cell);
      }
      return;
    }
    worker.inside.push_back(cell);
    return;
  }
  if (cell.level == 0) {
    worker.boundary.push_back(cell);
    ++worker.limited_by[std::string(kinematics::status_identifier(settling.why.code))];
    return;
  }
  refine_children(worker, grid, cell, settling.open);
}

void refine_children(Worker& worker, const Grid& grid, const CellIndex& cell,
                     const std::vector<OrientationBox>& open) {
  const std::int32_t half = std::int32_t{1} << (cell.level - 1);
  for (int child = 0; child < 8; ++child) {
    CellIndex next{cell.at, cell.level - 1};
    bool duplicate = false;
    for (int axis = 0; axis < 3; ++axis) {
      if (!((child >> axis) & 1)) continue;
      if (!grid.spans[static_cast<std::size_t>(axis)]) duplicate = true;
      next.at[static_cast<std::size_t>(axis)] += half;
    }
    if (!duplicate) refine(worker, grid, next, open);
  }
}

struct TopCells {
  std::vector<CellIndex> cells;
  int level = 0;
};

// Top cells of side 2^level steps, at most 8 along the longest spanned axis; dims rounded up to
// whole top cells.
TopCells top_cells(const Eigen::Vector3d& size_mm, const std::array<bool, 3>& spans, double step_mm,
                   std::array<int, 3>& dims) {
  double longest = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (spans[static_cast<std::size_t>(axis)]) longest = std::max(longest, size_mm[axis]);
  }
  TopCells top;
  while (step_mm * std::ldexp(1.0, top.level) * 8.0 < longest && top.level < 24) ++top.level;
  const int side = 1 << top.level;
  std::array<int, 3> count{1, 1, 1};
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    if (!spans[a]) {
      dims[a] = 1;
      continue;
    }
    count[a] = std::max(1, static_cast<int>(std::ceil(size_mm[axis] / (step_mm * side) - 1e-9)));
    dims[a] = count[a] * side;
  }
  for (int i = 0; i < count[0]; ++i) {
    for (int j = 0; j < count[1]; ++j) {
      for (int k = 0; k < count[2]; ++k) {
        top.cells.push_back({{i * side, j * side, k * side}, top.level});
      }
    }
  }
  // Axes not spanned stay at index 0.
  for (CellIndex& cell : top.cells) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!spans[static_cast<std::size_t>(axis)]) cell.at[static_cast<std::size_t>(axis)] = 0;
    }
  }
  return top;
}

}  // namespace

namespace {

// The orientation range as the one box every top cell starts from: the controlled angles only.
OrientationBox orientation_range(const machine::Machine& machine, const WorkspaceOptions& options) {
  OrientationBox box;
  for (int k = 0; k < 3; ++k) {
    const double lo = options.orientation_min_rad[k], hi = options.orientation_max_rad[k];
    if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) {
      throw std::invalid_argument("orientation range " + std::string(geometry::kAxisNames[3 + k]) +
                                  " is empty or not finite: give min <= max");
    }
    if (machine.kinematics().dof().controls(3 + k)) {
      box.centre[k] = 0.5 * (lo + hi);
      box.half[k] = 0.5 * (hi - lo);
    } else {
      box.centre[k] = machine.home().orientation_rad[k];
    }
  }
  return box;
}

// Runs the refinement of every top cell on `threads` workers; the findings in top-cell order.
void refine_all(const machine::Machine& machine, const Grid& grid, const TopCells& top,
                const OrientationBox& range, int threads, int dimensions, Workspace& result) {
  std::vector<std::unique_ptr<Worker>> parts(top.cells.size());
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto work = [&] {
    try {
      for (std::size_t k = next++; k < top.cells.size(); k = next++) {
        auto worker = std::make_unique<Worker>(machine);
        worker->dimensions = dimensions;
        refine(*worker, grid, top.cells[k], {range});
        parts[k] = std::move(worker);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = top.cells.size();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
  // Each part's cells freed once copied: the lists are most of the memory at a fine resolution.
  std::size_t inside = 0, boundary = 0;
  for (const auto& part : parts) {
    inside += part->inside.size();
    boundary += part->boundary.size();
  }
  result.inside.reserve(inside);
  result.boundary.reserve(boundary);
  for (const auto& part : parts) {
    result.inside.insert(result.inside.end(), part->inside.begin(), part->inside.end());
    result.boundary.insert(result.boundary.end(), part->boundary.begin(), part->boundary.end());
    std::vector<CellIndex>().swap(part->inside);
    std::vector<CellIndex>().swap(part->boundary);
    for (const auto& [name, count] : part->limited_by) result.limited_by[name] += count;
    result.cells_judged += part->judged;
    result.boxes_judged += part->poses_judged;
    result.unbounded_refusals += part->unbounded_refusals;
  }
}

// A cell's place in the sample of boundary cells the estimate visits: a hash of its indices,
// so the sample does not depend on the order the threads found the cells in.
std::uint64_t cell_hash(const CellIndex& cell) {
  std::uint64_t h = 0x9e3779b97f4a7c15u;
  for (const std::int32_t index : cell.at) {
    h ^= static_cast<std::uint32_t>(index);
    h *= 0xbf58476d1ce4e5b9u;
    h ^= h >> 31;
  }
  return h;
}

// The measure of the boundary cells' reachable share (reachable_share), from every cell up to
// kEstimateCells of them, beyond that from a sample of about that many chosen by cell_hash and
// scaled to all: an estimate either way (docs/workspace.md, "What a cell's answer means").
double estimate_boundary(const machine::Machine& machine, const Grid& grid,
                         const std::vector<CellIndex>& boundary, int threads, int dimensions) {
  constexpr std::size_t kEstimateCells = 250'000;
  if (boundary.empty()) return 0.0;
  const std::uint64_t stride = std::max<std::uint64_t>(1, boundary.size() / kEstimateCells);
  std::vector<const CellIndex*> sample;
  for (const CellIndex& cell : boundary) {
    if (stride == 1 || cell_hash(cell) % stride == 0) sample.push_back(&cell);
  }
  if (sample.empty()) sample.push_back(&boundary.front());
  std::vector<double> share(static_cast<std::size_t>(std::max(1, threads)), 0.0);
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto work = [&](std::size_t part) {
    try {
      for (std::size_t k = next++; k < sample.size(); k = next++) {
        share[part] += reachable_share(machine, position_cell(grid, *sample[k]), grid.range);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = sample.size();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < share.size(); ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
  double reached = 0.0;
  for (const double part : share) reached += part;
  return reached * std::pow(grid.step_mm, dimensions) * static_cast<double>(boundary.size()) /
         static_cast<double>(sample.size());
}

double measure(const std::vector<CellIndex>& cells, double step_mm, int dimensions) {
  double total = 0.0;
  for (const CellIndex& cell : cells) {
    total += std::pow(step_mm * std::ldexp(1.0, cell.level), dimensions);
  }
  return total;
}

std::optional<Eigen::AlignedBox3d> extent_of(const Workspace& ws, const Eigen::Vector3d& fixed) {
  if (ws.inside.empty() && ws.boundary.empty()) return std::nullopt;
  Eigen::AlignedBox3d box{Eigen::Vector3d::Constant(INFINITY),
                          Eigen::Vector3d::Constant(-INFINITY)};
  for (const auto* cells : {&ws.inside, &ws.boundary}) {
    for (const CellIndex& cell : *cells) {
      const int side = 1 << cell.level;
      for (int axis = 0; axis < 3; ++axis) {
        const auto a = static_cast<std::size_t>(axis);
        if (!ws.position_axes[a]) continue;
        const double lo = ws.origin_mm[axis] + ws.resolution_mm * cell.at[a];
        box.min()[axis] = std::min(box.min()[axis], lo);
        box.max()[axis] = std::max(box.max()[axis], lo + ws.resolution_mm * side);
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!ws.position_axes[static_cast<std::size_t>(axis)])
      box.min()[axis] = box.max()[axis] = fixed[axis];
  }
  return box;
}

}  // namespace

namespace {

// The grid and top cells of a run at `step_mm` over the search box.
struct Layout {
  Grid grid;
  TopCells top;
  std::array<int, 3> dims{};
  int dimensions = 0;
  bool empty = false;  // the search box is empty
};

Layout layout(const machine::Machine& machine, const SearchBox& search, const OrientationBox& range,
              double step_mm) {
  const kinematics::Kinematics& model = machine.kinematics();
  Layout result;
  Grid& grid = result.grid;
  grid.range = range;
  for (int axis = 0; axis < 3; ++axis) {
    grid.spans[static_cast<std::size_t>(axis)] = model.dof().controls(axis);
    result.dimensions += model.dof().controls(axis) ? 1 : 0;
  }
  grid.fixed = machine.home().position_mm;
  grid.step_mm = step_mm;
  grid.angle_scale_mm = bounds::pose_angle_scale_mm(model);
  const Eigen::Vector3d size = (search.box.max() - search.box.min()).cwiseMax(0.0);
  result.top = top_cells(size, grid.spans, grid.step_mm, result.dims);
  for (int axis = 0; axis < 3; ++axis) {
    if (!grid.spans[static_cast<std::size_t>(axis)]) {
      grid.origin_mm[axis] = grid.fixed[axis];
      continue;
    }
    result.empty = result.empty || !(search.box.max()[axis] >= search.box.min()[axis]);
    // Cells start at the box's low side: a side the machine's limits set exactly (a pass-through
    // joint's min, the envelope's) falls between cells rather than through them.
    grid.origin_mm[axis] = search.box.min()[axis];
  }
  return result;
}

// The power of two by which the estimate's run is coarser than the resolution (0: the run is
// small enough to be its own estimate).
int estimate_halvings(const Layout& fine) {
  int longest = 1;
  for (const int cells : fine.dims) longest = std::max(longest, cells);
  int halvings = 0;
  while ((longest >> halvings) > kEstimateSteps) ++halvings;
  return halvings;
}

CellEstimate estimate_at(const machine::Machine& machine, const WorkspaceOptions& options,
                         const SearchBox& search, const OrientationBox& range, int halvings) {
  Layout coarse = layout(machine, search, range, std::ldexp(options.resolution_mm, halvings));
  std::atomic<std::int64_t> judged{0};
  coarse.grid.judged = &judged;
  coarse.grid.max_cells = std::numeric_limits<std::int64_t>::max();
  Workspace run;
  if (!coarse.empty) {
    refine_all(machine, coarse.grid, coarse.top, range, options.threads, coarse.dimensions, run);
  }
  CellEstimate estimate;
  estimate.from_resolution_mm = coarse.grid.step_mm;
  estimate.growth = 1 << std::max(0, coarse.dimensions - 1);
  const double scale = std::pow(estimate.growth, halvings);
  estimate.run_judged = run.cells_judged;
  estimate.judged = static_cast<double>(run.cells_judged) * scale;
  estimate.listed = static_cast<double>(run.inside.size() + run.boundary.size()) * scale;
  estimate.bytes = 2.0 * estimate.listed * sizeof(CellIndex);
  return estimate;
}

// Runs from the coarsest (at most kEstimateSteps cells along the longest side) one halving finer
// at a time, until a run judges kEstimateRunCells (its boundary resolved well enough to scale)
// or the next run would be the resolution's own: a coarse run of a machine that fills little of
// its search box counts too few cells (Hektor at 8 mm, 0.6 times what scaling needs).
CellEstimate estimate_by_runs(const machine::Machine& machine, const WorkspaceOptions& options,
                              const SearchBox& search, const OrientationBox& range, int halvings) {
  CellEstimate estimate = estimate_at(machine, options, search, range, halvings);
  while (halvings > 1 && estimate.run_judged < kEstimateRunCells) {
    estimate = estimate_at(machine, options, search, range, --halvings);
  }
  return estimate;
}

// The estimate first, as plan's: a resolution too fine for the machine is refused before its
// cells fill the memory, naming the finest that fits.
void refuse_past_cell_bound(const machine::Machine& machine, const WorkspaceOptions& options,
                            const SearchBox& search, const OrientationBox& range,
                            const Layout& fine) {
  const int halvings = estimate_halvings(fine);
  if (halvings == 0 || fine.empty) return;
  const CellEstimate estimate = estimate_by_runs(machine, options, search, range, halvings);
  const auto bound = static_cast<double>(options.max_cells);
  if (estimate.judged <= bound) return;
  double fitting_mm = 0.0;
  if (estimate.growth > 1) {
    // The count goes as resolution^-(d - 1); 5 % to spare for the estimate's error (2 % on the
    // example machines).
    const double exponent = std::log2(static_cast<double>(estimate.growth));
    const double exact =
        options.resolution_mm * std::pow(1.05 * estimate.judged / bound, 1.0 / exponent);
    const double digit = std::pow(10.0, std::floor(std::log10(exact)) - 1.0);
    fitting_mm = std::ceil(exact / digit) * digit;
  }
  char text[400];
  std::snprintf(text, sizeof text,
                "at %g mm resolution the workspace would judge about %.3g cells and list %.3g "
                "(about %.3g GB), more than the bound of %lld cells (estimated from a run at "
                "%g mm, the count growing %d times with each halving)",
                options.resolution_mm, estimate.judged, estimate.listed, estimate.bytes / 1e9,
                static_cast<long long>(options.max_cells), estimate.from_resolution_mm,
                estimate.growth);
  std::string message = text;
  if (fitting_mm > 0.0) {
    std::snprintf(text, sizeof text, ": a resolution of %g mm or coarser fits", fitting_mm);
    message += text;
  }
  throw CellBoundError(message, estimate, fitting_mm);
}

}  // namespace

CellEstimate estimate_cells(const machine::Machine& machine, const WorkspaceOptions& options) {
  const OrientationBox range = orientation_range(machine, options);
  const SearchBox search = search_box(machine, options);
  const Layout fine = layout(machine, search, range, options.resolution_mm);
  return estimate_by_runs(machine, options, search, range, estimate_halvings(fine));
}

Workspace compute_workspace(const machine::Machine& machine, const WorkspaceOptions& options) {
  if (!(options.resolution_mm > 0.0) || !std::isfinite(options.resolution_mm)) {
    throw std::invalid_argument("the resolution must be a positive length (mm)");
  }
  Workspace ws;
  ws.machine = machine.name();
  ws.resolution_mm = options.resolution_mm;
  const OrientationBox range = orientation_range(machine, options);
  ws.orientation_min_rad = range.centre - range.half;
  ws.orientation_max_rad = range.centre + range.half;
  const SearchBox search = search_box(machine, options);
  if (!search.proven) {
    ws.notes.push_back(
        "the search box comes from the extent through home, widened by half: cells beyond it "
        "were not searched");
  }
  Layout fine = layout(machine, search, range, options.resolution_mm);
  refuse_past_cell_bound(machine, options, search, range, fine);
  Grid& grid = fine.grid;
  const int dimensions = fine.dimensions;
  std::atomic<std::int64_t> judged{0};
  grid.judged = &judged;
  grid.max_cells = options.max_cells;
  ws.position_axes = grid.spans;
  ws.planar = dimensions == 2 && !machine.kinematics().dof().controls(2);
  ws.dims = fine.dims;
  ws.origin_mm = grid.origin_mm;
  if (!fine.empty) refine_all(machine, grid, fine.top, range, options.threads, dimensions, ws);
  for (const auto& constraint : machine_constraints(machine)) {
    if (!constraint->proven()) {
      ws.guaranteed = false;
      ws.notes.push_back(
          "this model's reach (or its cables' tensions) is sampled at each cell's centre and "
          "corners, not bounded: cells are judged from those samples, not proven");
      break;
    }
  }
  if (ws.unbounded_refusals > 0) {
    ws.guaranteed = false;
    ws.notes.push_back(std::to_string(ws.unbounded_refusals) +
                       " cells the bounds proved inside were refused by the machine at their "
                       "middle: it applies a limit no constraint bounds here (they were split, "
                       "and left as boundary)");
  }
  ws.inside_measure = measure(ws.inside, grid.step_mm, dimensions);
  ws.boundary_measure = measure(ws.boundary, grid.step_mm, dimensions);
  ws.estimate = ws.inside_measure +
                estimate_boundary(machine, grid, ws.boundary, options.threads, dimensions);
  ws.extent = extent_of(ws, grid.fixed);
  const InscribedShapes shapes = largest_inscribed(ws);
  ws.largest_box = shapes.box;
  ws.largest_cylinder = shapes.cylinder;
  ws.maps = plane_maps(machine, ws, options.map_points);
  return ws;
}

}  // namespace pkm::workspace
