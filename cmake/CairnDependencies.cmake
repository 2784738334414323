find_package(PkgConfig REQUIRED)
# All third-party packages, found once. Every one comes from Debian 12 (scripts/install_deps.sh).
find_package(Threads REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Ceres REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs video features2d)
# QUIET: PCL announces on stderr that its optional pcap and png io features are off (Cairn uses
# neither); a missing PCL still stops the configure (REQUIRED).
find_package(PCL QUIET REQUIRED COMPONENTS common io filters search kdtree features registration sample_consensus)
find_package(octomap REQUIRED)
find_package(fastcdr REQUIRED)
find_package(fastrtps REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
find_package(spdlog REQUIRED)
find_package(CLI11 REQUIRED)
find_package(SQLite3 REQUIRED)
find_package(ZLIB REQUIRED)

pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
if(CAIRN_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(CAIRN_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()

# PCL's config exports include dirs/defs as variables; wrap them in one target so only the
# translation units that link cairn::pcl pay for its headers.
add_library(cairn_pcl INTERFACE)
target_include_directories(cairn_pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(cairn_pcl INTERFACE ${PCL_LIBRARIES})
target_compile_definitions(cairn_pcl INTERFACE ${PCL_DEFINITIONS})
add_library(cairn::pcl ALIAS cairn_pcl)

add_library(cairn_octomap INTERFACE)
target_include_directories(cairn_octomap SYSTEM INTERFACE ${OCTOMAP_INCLUDE_DIRS})
target_link_libraries(cairn_octomap INTERFACE ${OCTOMAP_LIBRARIES})
add_library(cairn::octomap ALIAS cairn_octomap)
