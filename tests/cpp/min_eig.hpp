// Test helper: the smallest eigenvalue of a symmetric matrix (shared by the random-matrix tests).
#pragma once

#include <Eigen/Dense>

inline double min_eig(const Eigen::MatrixXd& A) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues()(0);
}
