// Uses the installed library as a downstream project would: a plane of points with
// one far outlier, cleaned through a pcl::Filter pointer.
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>

#include <pcl/point_types.h>

#include <cstdio>

int
main ()
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j)
      cloud->push_back (pcl::PointXYZ (0.01f * i, 0.01f * j, 0.0f));
  cloud->push_back (pcl::PointXYZ (5.0f, 5.0f, 5.0f));
  pcl::Filter<pcl::PointXYZ>::Ptr filter (
      new pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ>);
  filter->setInputCloud (cloud);
  pcl::PointCloud<pcl::PointXYZ> out;
  filter->filter (out);
  std::printf ("consumer: %zu -> %zu points\n", cloud->size (), out.size ());
  return out.size () == 2500 ? 0 : 1;
}
