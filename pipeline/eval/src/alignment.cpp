#include "vifusion/eval/alignment.hpp"

#include <Eigen/SVD>

#include "vifusion/core/error.hpp"

namespace vifusion::eval {

SE3d alignRigid(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector3d>& data) {
  if (model.size() != data.size()) throw Error("alignRigid: point sets differ in size");
  if (model.size() < 3) throw Error("alignRigid: need at least 3 point pairs, got " + std::to_string(model.size()));

  Eigen::Vector3d model_mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d data_mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) {
    model_mean += model[i];
    data_mean += data[i];
  }
  model_mean /= static_cast<double>(model.size());
  data_mean /= static_cast<double>(data.size());

  Eigen::Matrix3d W = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) W += (model[i] - model_mean) * (data[i] - data_mean).transpose();

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(W.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& U = svd.matrixU();
  const Eigen::Matrix3d Vh = svd.matrixV().transpose();
  // Without this the closed form returns a reflection when the points are (nearly) planar or very noisy.
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (U.determinant() * Vh.determinant() < 0.0) S(2, 2) = -1.0;
  const Eigen::Matrix3d R = U * S * Vh;
  return SE3d(Eigen::Quaterniond(R), data_mean - R * model_mean);
}

SE3d alignPoses(const std::vector<SE3d>& model, const std::vector<SE3d>& data) {
  if (model.size() != data.size()) throw Error("alignPoses: pose sets differ in size");
  if (model.empty()) throw Error("alignPoses: no pose pairs");
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) sum += data[i].rotationMatrix() * model[i].rotationMatrix().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  const Eigen::Matrix3d R = svd.matrixU() * S * svd.matrixV().transpose();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) t += data[i].translation() - R * model[i].translation();
  t /= static_cast<double>(model.size());
  return SE3d(Eigen::Quaterniond(R), t);
}

}  // namespace vifusion::eval
