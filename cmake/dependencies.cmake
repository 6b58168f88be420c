# Third-party dependencies, all from Debian 12 packages (README, first command).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Ceres REQUIRED)
find_package(CGAL REQUIRED)
# Debian 12: VTK (pulled in by PCL) references MPI::MPI_C; find it before PCL.
find_package(MPI COMPONENTS C QUIET)
find_package(PCL 1.12 REQUIRED COMPONENTS common io kdtree search sample_consensus segmentation)
find_package(OpenCASCADE REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(FastFloat QUIET)
if(NOT TARGET FastFloat::fast_float)
  find_path(FAST_FLOAT_INCLUDE_DIR fast_float/fast_float.h REQUIRED)
  add_library(FastFloat::fast_float INTERFACE IMPORTED)
  target_include_directories(FastFloat::fast_float INTERFACE ${FAST_FLOAT_INCLUDE_DIR})
endif()
find_package(GTest REQUIRED)
find_package(Threads REQUIRED)
find_package(TBB REQUIRED)  # oneTBB: the one shared thread pool (core/parallel.cc)
if(TPCAL_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()

# PCL and OpenCASCADE as imported interface targets, so modules link them PRIVATE only.
add_library(tpcal_pcl INTERFACE)
target_include_directories(tpcal_pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(tpcal_pcl INTERFACE ${PCL_LIBRARIES})
target_compile_definitions(tpcal_pcl INTERFACE ${PCL_DEFINITIONS})
add_library(tpcal::pcl ALIAS tpcal_pcl)

add_library(tpcal_occt INTERFACE)
target_include_directories(tpcal_occt SYSTEM INTERFACE ${OpenCASCADE_INCLUDE_DIR})
target_link_libraries(tpcal_occt INTERFACE TKSTEP TKSTEPBase TKSTEPAttr TKSTEP209 TKXSBase
  TKPrim TKBO TKTopAlgo TKBRep TKGeomAlgo TKG3d TKG2d TKGeomBase TKMath TKernel TKShHealing TKFillet TKOffset TKMesh)
add_library(tpcal::occt ALIAS tpcal_occt)

# libxxhash (Debian libxxhash-dev): the point-file digest of result.json.
find_path(XXHASH_INCLUDE_DIR xxhash.h REQUIRED)
find_library(XXHASH_LIBRARY xxhash REQUIRED)
add_library(tpcal_xxhash INTERFACE)
target_include_directories(tpcal_xxhash SYSTEM INTERFACE ${XXHASH_INCLUDE_DIR})
target_link_libraries(tpcal_xxhash INTERFACE ${XXHASH_LIBRARY})
add_library(tpcal::xxhash ALIAS tpcal_xxhash)

# libxml2 (Debian libxml2-dev): the QIF reader's streaming XML parser (tpcal::io, PRIVATE).
find_package(LibXml2 REQUIRED)  # imported target LibXml2::LibXml2
