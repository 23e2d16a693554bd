#include "pkm/calibration/distance_fit.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include "pkm/calibration/measurements.hpp"

namespace pkm::calibration {

namespace {

constexpr double kLargestDistance_mm = 1e6;
// A parameter direction whose effect on the marks is rigid but for less than this share (by
// size) only moves the whole drawing, far below a tape's resolution: turning a hanging
// plotter's frame on pulleys is rigid but for 3e-7, moving a light gondola's attachment point
// with its anchor but for 0.6 %.
// A genuine but weak direction shares more: about 5 % for the joint offsets of a hanging
// plotter, which move the pen mostly up and down the sheet alike.
constexpr double kRigidShare = 0.01;

int mark_index(const std::string& text, const std::vector<PatternMark>& marks,
               const std::function<void(const std::string&)>& fail) {
  int id = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), id);
  if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size())
    fail("'" + text + "' is not a mark number");
  for (std::size_t i = 0; i < marks.size(); ++i) {
    if (marks[i].id == id) return static_cast<int>(i);
  }
  fail("mark " + text + " is not in the pattern (its marks: " + std::to_string(marks.front().id) +
       " .. " + std::to_string(marks.back().id) + ")");
  return -1;
}

// The header's columns: which field is mark_a, mark_b, distance_mm.
std::array<int, 3> header_columns(const std::vector<CsvField>& header,
                                  const std::function<void(int, const std::string&)>& fail) {
  const std::array<std::string, 3> names{"mark_a", "mark_b", "distance_mm"};
  std::array<int, 3> columns{-1, -1, -1};
  for (std::size_t c = 0; c < header.size(); ++c) {
    const auto name = std::find(names.begin(), names.end(), header[c].text);
    if (name == names.end())
      fail(header[c].column,
           "unknown column '" + header[c].text + "' (expected mark_a,mark_b,distance_mm)");
    int& column = columns[static_cast<std::size_t>(name - names.begin())];
    if (column >= 0) fail(header[c].column, "column '" + header[c].text + "' appears twice");
    column = static_cast<int>(c);
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (columns[k] < 0) fail(1, "no column '" + names[k] + "' (header mark_a,mark_b,distance_mm)");
  }
  return columns;
}

// The residuals of a geometry: for each measured pair, the distance between the pen positions
// FK gives for the joints the marks were drawn with, minus the measured distance.
class DistanceResiduals final : public ParameterResiduals {
 public:
  DistanceResiduals(const kinematics::Kinematics& kinematics, const geometry::Pose& home,
                    const std::vector<PatternMark>& marks,
                    const std::vector<MarkDistance>& distances)
      : model_(kinematics.clone()), distances_(distances) {
    for (const PatternMark& mark : marks) {
      geometry::Pose pose = home;
      pose.position_mm.x() = mark.position_mm.x();
      pose.position_mm.y() = mark.position_mm.y();
      kinematics::JointVector joints;
      const kinematics::Status status = kinematics.inverse(pose, joints);
      if (!status.ok()) {
        throw FitError((mark.location.empty() ? "" : mark.location + ": ") + "mark " +
                       std::to_string(mark.id) + " is outside the nominal model's reach (" +
                       kinematics::describe(status) +
                       "): the pattern was drawn with another machine file?");
      }
      seeds_.push_back(pose);
      joints_.push_back(joints);
    }
  }

  int count() const override { return static_cast<int>(distances_.size()); }
  int mark_count() const { return static_cast<int>(seeds_.size()); }
  const std::vector<geometry::Pose>& nominal_poses() const { return seeds_; }

  // The pen positions (x y z per mark, mm) the geometry gives for the drawn joints.
  bool positions(std::span<const double> parameters, double* out) const {
    try {
      model_->set_parameters(parameters);
    } catch (const std::invalid_argument&) {
      return false;
    }
    for (std::size_t k = 0; k < seeds_.size(); ++k) {
      geometry::Pose pose = seeds_[k];
      if (!model_->forward(joints_[k], pose).ok()) return false;
      for (int axis = 0; axis < 3; ++axis) out[3 * k + axis] = pose.position_mm[axis];
    }
    return true;
  }

  bool evaluate(std::span<const double> parameters, double* residuals) const override {
    std::vector<double> pen(3 * seeds_.size());
    if (!positions(parameters, pen.data())) return false;
    for (std::size_t i = 0; i < distances_.size(); ++i) {
      const MarkDistance& d = distances_[i];
      const Eigen::Map<const Eigen::Vector3d> a(&pen[3 * static_cast<std::size_t>(d.a)]);
      const Eigen::Map<const Eigen::Vector3d> b(&pen[3 * static_cast<std::size_t>(d.b)]);
      residuals[i] = (a - b).norm() - d.distance_mm;
    }
    return true;
  }

  void summarise(const std::vector<double>& residuals, double& rms, double& max,
                 int& max_line) const override {
    double sum = 0.0;
    max = 0.0;
    for (std::size_t i = 0; i < residuals.size(); ++i) {
      sum += residuals[i] * residuals[i];
      if (std::abs(residuals[i]) > max) max = std::abs(residuals[i]), max_line = distances_[i].line;
    }
    rms = std::sqrt(sum / static_cast<double>(residuals.size()));
  }

  std::string nominal_failure_hint() const override {
    return "forward kinematics fails for the joints a mark was drawn with";
  }

  double extent_mm() const override {
    Eigen::AlignedBox3d box;
    for (const geometry::Pose& pose : seeds_) box.extend(pose.position_mm);
    return seeds_.empty() ? 0.0 : box.diagonal().norm();
  }

 private:
  std::unique_ptr<kinematics::Kinematics> model_;
  const std::vector<MarkDistance>& distances_;
  std::vector<geometry::Pose> seeds_;
  std::vector<kinematics::JointVector> joints_;
};

// The rigid motions of the marks over the coordinates the machine moves in (translations
// along each, rotations in each pair about the marks' centroid), as orthonormal columns.
Eigen::MatrixXd rigid_motions(const std::vector<geometry::Pose>& marks, geometry::Dof dof) {
  const auto n = static_cast<Eigen::Index>(marks.size());
  std::vector<int> axes;
  for (int axis = 0; axis < 3; ++axis) {
    if (dof.controls(axis)) axes.push_back(axis);
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const geometry::Pose& pose : marks) centroid += pose.position_mm / static_cast<double>(n);
  std::vector<Eigen::VectorXd> columns;
  for (const int axis : axes) {
    Eigen::VectorXd column = Eigen::VectorXd::Zero(3 * n);
    for (Eigen::Index k = 0; k < n; ++k) column[3 * k + axis] = 1.0;
    columns.push_back(column);
  }
  for (std::size_t i = 0; i < axes.size(); ++i) {
    for (std::size_t j = i + 1; j < axes.size(); ++j) {
      Eigen::VectorXd column = Eigen::VectorXd::Zero(3 * n);
      for (Eigen::Index k = 0; k < n; ++k) {
        const Eigen::Vector3d r = marks[static_cast<std::size_t>(k)].position_mm - centroid;
        column[3 * k + axes[i]] = -r[axes[j]];
        column[3 * k + axes[j]] = r[axes[i]];
      }
      columns.push_back(column);
    }
  }
  Eigen::MatrixXd generators(3 * n, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c)
    generators.col(static_cast<Eigen::Index>(c)) = columns[c];
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(generators);
  return qr.householderQ() * Eigen::MatrixXd::Identity(3 * n, generators.cols());
}

// The requested parameters to hold so that no free direction of parameter space only moves the
// whole drawing: the directions whose motion of the marks is rigid but for less than
// kRigidShare, and for them the first parameters in the model's order that carry them (on a
// hanging plotter the left anchor, where the drawing sits, and the right one's height, how it is
// turned).
std::vector<std::string> rigid_motion_parameters(const DistanceResiduals& residuals,
                                                 const kinematics::Kinematics& kinematics,
                                                 const std::vector<int>& requested) {
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : parameters) nominal.push_back(p.value);
  Eigen::MatrixXd motion;
  const auto positions = [&](std::span<const double> p, double* out) {
    return residuals.positions(p, out);
  };
  if (!parameter_jacobian(positions, 3 * residuals.mark_count(), nominal, requested, motion))
    return {};
  std::vector<int> seen;  // columns of `motion` that move the marks at all
  const double largest = motion.cols() ? motion.colwise().norm().maxCoeff() : 0.0;
  for (Eigen::Index c = 0; c < motion.cols(); ++c) {
    if (motion.col(c).norm() > 1e-9 * largest) seen.push_back(static_cast<int>(c));
  }
  if (seen.empty()) return {};
  Eigen::MatrixXd scaled(motion.rows(), static_cast<Eigen::Index>(seen.size()));
  for (std::size_t c = 0; c < seen.size(); ++c)
    scaled.col(static_cast<Eigen::Index>(c)) = motion.col(seen[c]) / motion.col(seen[c]).norm();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& singular = svd.singularValues();
  Eigen::Index rank = 0;
  while (rank < singular.size() && singular[rank] > 1e-9 * singular[0]) ++rank;
  // In the range of the motions, the share of each direction that is not rigid: the
  // eigenvalues of U^T (I - Q Q^T) U, Q the rigid motions.
  const Eigen::MatrixXd u = svd.matrixU().leftCols(rank);
  const Eigen::MatrixXd rigid = rigid_motions(residuals.nominal_poses(), kinematics.dof());
  const Eigen::MatrixXd in_rigid = rigid.transpose() * u;
  const Eigen::MatrixXd non_rigid =
      Eigen::MatrixXd::Identity(rank, rank) - in_rigid.transpose() * in_rigid;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(non_rigid);
  std::vector<Eigen::VectorXd> directions;
  for (Eigen::Index k = 0; k < rank; ++k) {
    if (eigen.eigenvalues()[k] >= kRigidShare * kRigidShare) continue;
    const Eigen::VectorXd w = eigen.eigenvectors().col(k);
    directions.push_back(svd.matrixV().leftCols(rank) *
                         (w.array() / singular.head(rank).array()).matrix());
  }
  if (directions.empty()) return {};
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(seen.size()),
                        static_cast<Eigen::Index>(directions.size()));
  for (std::size_t k = 0; k < directions.size(); ++k)
    basis.col(static_cast<Eigen::Index>(k)) = directions[k];
  const Eigen::HouseholderQR<Eigen::MatrixXd> orthonormal(basis);
  const Eigen::MatrixXd q =
      orthonormal.householderQ() * Eigen::MatrixXd::Identity(basis.rows(), basis.cols());
  // In the model's order, hold each parameter that carries a rigid motion the ones held so far
  // do not: its row of q (its share of each rigid direction), less what the held rows span.
  std::vector<int> held;
  Eigen::MatrixXd held_rows(0, q.cols());
  const double largest_row = q.rowwise().norm().maxCoeff();
  for (Eigen::Index r = 0; r < q.rows() && held_rows.rows() < q.cols(); ++r) {
    Eigen::RowVectorXd row = q.row(r);
    if (row.norm() < 0.1 * largest_row) continue;
    for (Eigen::Index h = 0; h < held_rows.rows(); ++h)
      row -= row.dot(held_rows.row(h)) * held_rows.row(h);
    if (row.norm() < 0.5 * q.row(r).norm()) continue;
    held_rows.conservativeResize(held_rows.rows() + 1, Eigen::NoChange);
    held_rows.row(held_rows.rows() - 1) = row.normalized();
    held.push_back(requested[static_cast<std::size_t>(seen[static_cast<std::size_t>(r)])]);
  }
  std::vector<std::string> names;
  for (const int index : held) names.push_back(parameters[index].name);
  return names;
}

}  // namespace

std::vector<MarkDistance> parse_distances_csv(const std::string& text,
                                              const std::string& source_name,
                                              const std::vector<PatternMark>& marks) {
  int line_number = 0;
  const auto fail = [&](int column, const std::string& message) {
    throw MeasurementFileError(source_name + ":" + std::to_string(line_number) + ":" +
                               std::to_string(column) + ": " + message);
  };
  if (marks.empty()) fail(1, "the pattern has no marks");
  std::istringstream in(text);
  std::string line;
  std::array<int, 3> columns{};
  std::size_t field_count = 0;
  std::vector<MarkDistance> distances;
  std::map<std::pair<int, int>, int> line_of_pair;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<CsvField> fields = split_csv_line(line);
    if (field_count == 0) {
      columns = header_columns(fields, fail);
      field_count = fields.size();
      continue;
    }
    if (fields.size() != field_count) {
      fail(1, "has " + std::to_string(fields.size()) + " fields; the header has " +
                  std::to_string(field_count));
    }
    MarkDistance distance;
    distance.line = line_number;
    const CsvField& a = fields[static_cast<std::size_t>(columns[0])];
    const CsvField& b = fields[static_cast<std::size_t>(columns[1])];
    const CsvField& d = fields[static_cast<std::size_t>(columns[2])];
    distance.a = mark_index(a.text, marks, [&](const std::string& m) { fail(a.column, m); });
    distance.b = mark_index(b.text, marks, [&](const std::string& m) { fail(b.column, m); });
    if (distance.a == distance.b) fail(b.column, "a mark paired with itself");
    if (!csv_number(d.text, distance.distance_mm))
      fail(d.column, "'" + d.text + "' is not a number");
    if (!std::isfinite(distance.distance_mm)) fail(d.column, "the distance must be finite");
    if (!(distance.distance_mm > 0.0))
      fail(d.column, "the distance must be positive (mm), not " + d.text);
    if (distance.distance_mm > kLargestDistance_mm)
      fail(d.column, "'" + d.text + "' is beyond any machine (at most 1e6 mm)");
    const std::pair<int, int> pair(std::min(distance.a, distance.b),
                                   std::max(distance.a, distance.b));
    if (const auto seen = line_of_pair.find(pair); seen != line_of_pair.end()) {
      fail(a.column, "marks " + a.text + " and " + b.text + " were measured already at line " +
                         std::to_string(seen->second) +
                         " (average repeated readings into one row)");
    }
    line_of_pair[pair] = line_number;
    distances.push_back(distance);
  }
  if (field_count == 0) {
    line_number = std::max(line_number, 1);
    fail(1, "empty file: expected the header mark_a,mark_b,distance_mm");
  }
  if (distances.empty()) fail(1, "no distances after the header");
  return distances;
}

std::vector<MarkDistance> read_distances_csv(const std::filesystem::path& path,
                                             const std::vector<PatternMark>& marks) {
  return parse_distances_csv(read_text_file(path), path.string(), marks);
}

std::vector<MarkDistance> all_pairs(const std::vector<PatternMark>& marks) {
  std::vector<MarkDistance> pairs;
  for (std::size_t a = 0; a < marks.size(); ++a) {
    for (std::size_t b = a + 1; b < marks.size(); ++b) {
      pairs.push_back({static_cast<int>(a), static_cast<int>(b),
                       (marks[a].position_mm - marks[b].position_mm).norm(), 0});
    }
  }
  return pairs;
}

DistanceIdentification identify_from_distances(const kinematics::Kinematics& kinematics,
                                               const geometry::Pose& home,
                                               const std::vector<PatternMark>& marks,
                                               const std::vector<MarkDistance>& distances,
                                               const FitOptions& options) {
  const std::vector<int> requested = requested_parameters(kinematics, options.parameters);
  const DistanceResiduals residuals(kinematics, home, marks, distances);
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  DistanceIdentification result;
  result.held_rigid_motion = rigid_motion_parameters(residuals, kinematics, requested);
  const Identification identified = identify_at_nominal(
      kinematics, residuals, requested, result.held_rigid_motion, options.rank_tolerance);
  result.indistinguishable = identified.indistinguishable;
  result.no_effect = identified.no_effect;
  // How well a tape of the design noise would pin each: those it pins less well than the machine
  // file does are held, as the fit would hold them.
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : parameters) nominal.push_back(p.value);
  Eigen::MatrixXd jacobian;
  const auto function = [&](std::span<const double> p, double* out) {
    return residuals.evaluate(p, out);
  };
  if (!identified.free.empty() &&
      parameter_jacobian(function, residuals.count(), nominal, identified.free, jacobian)) {
    result.poorly_determined = poorly_determined(
        jacobian, screened_parameters(kinematics, identified.free, nominal, residuals.extent_mm()),
        options.design_noise_mm);
  }
  for (const int index : identified.free) {
    const std::string& name = parameters[index].name;
    const bool poor = std::any_of(result.poorly_determined.begin(), result.poorly_determined.end(),
                                  [&](const PoorlyDetermined& p) { return p.name == name; });
    if (!poor) result.identified.push_back(name);
  }
  return result;
}

FitReport fit_distances(kinematics::Kinematics& kinematics, const geometry::Pose& home,
                        const std::vector<PatternMark>& marks,
                        const std::vector<MarkDistance>& distances, const FitOptions& options) {
  if (distances.empty()) throw FitError("no distances to fit");
  const std::vector<int> requested = requested_parameters(kinematics, options.parameters);
  const DistanceResiduals residuals(kinematics, home, marks, distances);
  const std::vector<std::string> rigid = rigid_motion_parameters(residuals, kinematics, requested);
  FitReport report = fit_parameters(kinematics, residuals, requested, rigid, options);
  report.measurements = static_cast<int>(distances.size());
  return report;
}

}  // namespace pkm::calibration
