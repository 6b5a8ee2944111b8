// PCL's two tabletop pipelines on the same PCD frames as `tabula bench frames`, timed
// the same way (CPU time of the calling thread, median over repetitions). Built and
// run by scripts/pcl_tabletop.sh; used only to measure the anchor, never by tabula.
//
// organized:   IntegralImageNormalEstimation (covariance, smoothing 10, depth change
//              0.02) → OrganizedMultiPlaneSegmentation (min 1,000 inliers, 3°, 2 cm,
//              refined) → OrganizedConnectedComponentSegmentation with a
//              EuclideanClusterComparator (1 cm, depth dependent) over the non-plane
//              points → clusters of ≥ 200 points.
// unorganized: the same points without their grid: StatisticalOutlierRemoval (k 10,
//              1 σ, SPEC §6) → SACSegmentation plane (RANSAC 1 cm, 1,000 iterations) →
//              ConvexHull of the plane → ExtractPolygonalPrismData (1 cm – 50 cm) →
//              EuclideanClusterExtraction (1 cm, ≥ 200 points).
#include <pcl/ModelCoefficients.h>
#include <pcl/features/integral_image_normal.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/euclidean_cluster_comparator.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/extract_polygonal_prism_data.h>
#include <pcl/segmentation/organized_connected_component_segmentation.h>
#include <pcl/segmentation/organized_multi_plane_segmentation.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <pcl/surface/convex_hull.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

using PointT = pcl::PointXYZ;
using Cloud = pcl::PointCloud<PointT>;

static double cpu_ms() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static size_t organized(const Cloud::ConstPtr &cloud) {
  pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
  pcl::IntegralImageNormalEstimation<PointT, pcl::Normal> ne;
  ne.setNormalEstimationMethod(ne.COVARIANCE_MATRIX);
  ne.setMaxDepthChangeFactor(0.02f);
  ne.setNormalSmoothingSize(10.0f);
  ne.setInputCloud(cloud);
  ne.compute(*normals);

  pcl::OrganizedMultiPlaneSegmentation<PointT, pcl::Normal, pcl::Label> mps;
  mps.setMinInliers(1000);
  mps.setAngularThreshold(3.0 * M_PI / 180.0);
  mps.setDistanceThreshold(0.02);
  mps.setInputNormals(normals);
  mps.setInputCloud(cloud);
  std::vector<pcl::PlanarRegion<PointT>, Eigen::aligned_allocator<pcl::PlanarRegion<PointT>>> regions;
  std::vector<pcl::ModelCoefficients> coefficients;
  std::vector<pcl::PointIndices> inliers, label_indices, boundaries;
  pcl::PointCloud<pcl::Label>::Ptr labels(new pcl::PointCloud<pcl::Label>);
  mps.segmentAndRefine(regions, coefficients, inliers, labels, label_indices, boundaries);

  auto exclude = std::make_shared<std::set<std::uint32_t>>();
  for (size_t i = 0; i < label_indices.size(); ++i)
    if (label_indices[i].indices.size() >= 1000) exclude->insert(i);
  auto comparator = std::make_shared<pcl::EuclideanClusterComparator<PointT, pcl::Label>>();
  comparator->setInputCloud(cloud);
  comparator->setLabels(labels);
  comparator->setExcludeLabels(exclude);
  comparator->setDistanceThreshold(0.01f, true);
  pcl::PointCloud<pcl::Label> cluster_labels;
  std::vector<pcl::PointIndices> clusters;
  pcl::OrganizedConnectedComponentSegmentation<PointT, pcl::Label> seg(comparator);
  seg.setInputCloud(cloud);
  seg.segment(cluster_labels, clusters);
  return std::count_if(clusters.begin(), clusters.end(),
                       [](const pcl::PointIndices &c) { return c.indices.size() >= 200; });
}

static size_t unorganized(const Cloud::ConstPtr &dense) {
  Cloud::Ptr kept(new Cloud);
  pcl::StatisticalOutlierRemoval<PointT> sor;
  sor.setInputCloud(dense);
  sor.setMeanK(10);
  sor.setStddevMulThresh(1.0);
  sor.filter(*kept);

  pcl::SACSegmentation<PointT> sac;
  sac.setOptimizeCoefficients(true);
  sac.setModelType(pcl::SACMODEL_PLANE);
  sac.setMethodType(pcl::SAC_RANSAC);
  sac.setDistanceThreshold(0.01);
  sac.setMaxIterations(1000);
  sac.setInputCloud(kept);
  pcl::PointIndices::Ptr plane(new pcl::PointIndices);
  pcl::ModelCoefficients::Ptr coefficients(new pcl::ModelCoefficients);
  sac.segment(*plane, *coefficients);
  if (plane->indices.size() < 3) return 0;

  Cloud::Ptr plane_points(new Cloud), hull(new Cloud);
  pcl::ExtractIndices<PointT> extract;
  extract.setInputCloud(kept);
  extract.setIndices(plane);
  extract.filter(*plane_points);
  pcl::ConvexHull<PointT> chull;
  chull.setInputCloud(plane_points);
  chull.setDimension(2);
  chull.reconstruct(*hull);

  pcl::PointIndices::Ptr prism(new pcl::PointIndices);
  pcl::ExtractPolygonalPrismData<PointT> prism_extract;
  prism_extract.setInputCloud(kept);
  prism_extract.setInputPlanarHull(hull);
  prism_extract.setHeightLimits(0.01, 0.5);
  prism_extract.segment(*prism);
  Cloud::Ptr above(new Cloud);
  extract.setIndices(prism);
  extract.filter(*above);

  pcl::search::KdTree<PointT>::Ptr tree(new pcl::search::KdTree<PointT>);
  tree->setInputCloud(above);
  std::vector<pcl::PointIndices> clusters;
  pcl::EuclideanClusterExtraction<PointT> ec;
  ec.setClusterTolerance(0.01);
  ec.setMinClusterSize(200);
  ec.setSearchMethod(tree);
  ec.setInputCloud(above);
  ec.extract(clusters);
  return clusters.size();
}

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char **argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s REPS FILE.pcd...\n", argv[0]);
    return 2;
  }
  int reps = std::max(1, std::atoi(argv[1]));
  for (int f = 2; f < argc; ++f) {
    Cloud::Ptr cloud(new Cloud);
    if (pcl::io::loadPCDFile(argv[f], *cloud) != 0) return 1;
    // Our frames hold the optical frame; PCL's sensor orientation must not rotate it.
    cloud->sensor_orientation_ = Eigen::Quaternionf::Identity();
    cloud->sensor_origin_ = Eigen::Vector4f::Zero();
    Cloud::Ptr dense(new Cloud);
    for (const auto &p : cloud->points)
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) dense->push_back(p);
    std::vector<double> org, unorg;
    size_t n_org = 0, n_unorg = 0;
    for (int r = 0; r < reps; ++r) {
      double t = cpu_ms();
      n_org = organized(cloud);
      org.push_back(cpu_ms() - t);
      t = cpu_ms();
      n_unorg = unorganized(dense);
      unorg.push_back(cpu_ms() - t);
    }
    std::printf(
        "{\"file\": \"%s\", \"points\": %zu, \"organized_ms\": %.1f, \"organized_clusters\": %zu, "
        "\"unorganized_ms\": %.1f, \"unorganized_clusters\": %zu}\n",
        argv[f], dense->size(), median(org), n_org, median(unorg), n_unorg);
  }
  return 0;
}
