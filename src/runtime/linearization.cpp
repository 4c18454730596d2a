#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/spd_solver.hpp>

namespace symdyn::runtime {

namespace {

Matrix select(const Matrix& X, const std::vector<int>& rows, const std::vector<int>& cols) {
  Matrix Y(rows.size(), cols.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < cols.size(); ++c) Y(r, c) = X(rows[r], cols[c]);
  }
  return Y;
}

void write_block(std::ostream& out, const char* name, const Matrix& X) {
  for (Eigen::Index r = 0; r < X.rows(); ++r) {
    out << name << ',' << r;
    for (Eigen::Index c = 0; c < X.cols(); ++c) out << fmt::format(",{}", X(r, c));
    out << '\n';
  }
}

}  // namespace

Linearization linearize(DynamicSystem& sys, const State& s, const LinearizationOptions& options) {
  const int n = sys.num_coordinates();
  std::vector<bool> locked(n, false);
  for (int j : options.locked) {
    if (j < 0 || j >= n) throw ModelError(fmt::format("linearize: no coordinate {} to lock", j));
    locked[j] = true;
  }
  Linearization lin;
  for (int j = 0; j < n; ++j) {
    if (locked[j]) continue;
    lin.kept.push_back(j);
    lin.coordinates.push_back(sys.coordinate_name(j));
  }
  Vector qdd, yd;
  if (options.qdd) {
    qdd = *options.qdd;
  } else {
    sys.accelerations(s, qdd, yd);
  }
  yd = Vector::Zero(sys.num_extra_states());
  Matrix M, C, K;
  sys.jacobians(s, qdd, M, C, K);
  lin.M = select(M, lin.kept, lin.kept);
  lin.C = select(C, lin.kept, lin.kept);
  lin.K = select(K, lin.kept, lin.kept);

  // B = -df/du by central differences on each input.
  const int nk = static_cast<int>(lin.kept.size());
  const int nu = static_cast<int>(options.inputs.size());
  lin.B.resize(nk, nu);
  Vector fp, fm, g;
  for (int c = 0; c < nu; ++c) {
    const Input& in = options.inputs[c];
    lin.inputs.push_back(in.name);
    const double u0 = in.get();
    const double h = options.input_step * std::max(1.0, std::abs(u0));
    in.set(u0 + h);
    sys.residual(s, qdd, yd, fp, g);
    in.set(u0 - h);
    sys.residual(s, qdd, yd, fm, g);
    in.set(u0);
    for (int r = 0; r < nk; ++r) lin.B(r, c) = -(fp(lin.kept[r]) - fm(lin.kept[r])) / (2.0 * h);
  }

  SpdSolver solver(nk);
  if (nk > 0 && !solver.factor(lin.M)) {
    // The model's reason (an angle sequence at its singular configuration) when it knows one.
    const auto why = sys.explain_singular(s, M);
    throw NumericError(fmt::format("linearize: mass matrix is singular or indefinite at t = {}: {}",
                                   s.t, why ? *why : mass_matrix_singularity(lin.M, [&](int r) {
                                     return sys.coordinate_name(lin.kept[r]);
                                   })));
  }
  const Eigen::LDLT<Matrix> ldlt(lin.M);
  lin.A = Matrix::Zero(2 * nk, 2 * nk);
  lin.A.topRightCorner(nk, nk).setIdentity();
  lin.A.bottomLeftCorner(nk, nk) = -ldlt.solve(lin.K);
  lin.A.bottomRightCorner(nk, nk) = -ldlt.solve(lin.C);
  lin.Bx = Matrix::Zero(2 * nk, nu);
  if (nu > 0) lin.Bx.bottomRows(nk) = ldlt.solve(lin.B);
  return lin;
}

std::vector<Mode> modes(const Linearization& lin) {
  const Eigen::Index n = lin.M.rows();
  std::vector<Mode> out;
  if (n == 0) return out;
  const Eigen::EigenSolver<Matrix> eig(lin.A);
  if (eig.info() != Eigen::Success) throw NumericError("modes: eigenvalue computation failed");
  const double scale = std::max(1.0, eig.eigenvalues().cwiseAbs().maxCoeff());
  for (Eigen::Index m = 0; m < 2 * n; ++m) {
    const std::complex<double> lambda = eig.eigenvalues()(m);
    const bool real = std::abs(lambda.imag()) <= 1e-12 * scale;
    if (!real && lambda.imag() < 0.0) continue;  // the conjugate of a listed pole
    Mode mode;
    mode.pole = real ? std::complex<double>(lambda.real(), 0.0) : lambda;
    const double mag = std::abs(mode.pole);
    mode.natural_frequency_hz = mag / (2.0 * std::numbers::pi);
    mode.damped_frequency_hz = std::abs(mode.pole.imag()) / (2.0 * std::numbers::pi);
    mode.damping_ratio = mag > 0.0 ? -mode.pole.real() / mag : 0.0;
    Eigen::VectorXcd psi = eig.eigenvectors().col(m).head(n);
    Eigen::Index big = 0;
    psi.cwiseAbs().maxCoeff(&big);
    if (std::abs(psi(big)) > 0.0) psi /= psi(big);
    mode.modal_mass = std::abs((psi.transpose() * lin.M.cast<std::complex<double>>() * psi)(0, 0));
    mode.shape = psi;
    out.push_back(std::move(mode));
  }
  std::sort(out.begin(), out.end(),
            [](const Mode& a, const Mode& b) { return std::abs(a.pole) < std::abs(b.pole); });
  return out;
}

void write_matrices_csv(std::ostream& out, const Linearization& lin) {
  out << "matrix,row";
  for (const auto& c : lin.coordinates) out << ',' << c;
  out << '\n';
  write_block(out, "M", lin.M);
  write_block(out, "C", lin.C);
  write_block(out, "K", lin.K);
  if (lin.B.cols() > 0) {
    out << "matrix,row";
    for (const auto& u : lin.inputs) out << ',' << u;
    out << '\n';
    write_block(out, "B", lin.B);
  }
}

void write_modes_csv(std::ostream& out, const Linearization& lin, const std::vector<Mode>& modes) {
  out << "mode,pole_re,pole_im,natural_frequency_hz,damped_frequency_hz,damping_ratio,modal_mass";
  for (const auto& c : lin.coordinates) out << ',' << c << "_re," << c << "_im";
  out << '\n';
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const Mode& md = modes[m];
    out << fmt::format("{},{},{},{},{},{},{}", m, md.pole.real(), md.pole.imag(),
                       md.natural_frequency_hz, md.damped_frequency_hz, md.damping_ratio,
                       md.modal_mass);
    for (Eigen::Index j = 0; j < md.shape.size(); ++j) {
      out << fmt::format(",{},{}", md.shape(j).real(), md.shape(j).imag());
    }
    out << '\n';
  }
}

}  // namespace symdyn::runtime
