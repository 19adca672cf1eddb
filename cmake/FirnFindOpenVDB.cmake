# OpenVDB for the VDB caches (engine/io/Vdb.cpp). Debian 12's libopenvdb-dev (10.0.1) installs no
# OpenVDBConfig.cmake; its FindOpenVDB.cmake module lives, with the modules it calls (FindTBB, FindBlosc,
# FindIlmBase …), in lib/<multiarch>/cmake/OpenVDB, which is put on the module path here. FindOpenVDB also needs
# Boost.Iostreams (libboost-iostreams-dev), which the package does not depend on; scripts/setup.sh installs both.
# FirnConfig.cmake runs this file too, so that a program linking the installed Firn::engine finds OpenVDB alike.
find_package(OpenVDB QUIET CONFIG)
if(NOT OpenVDB_FOUND)
  find_path(FIRN_OPENVDB_MODULE_DIR FindOpenVDB.cmake
            PATH_SUFFIXES lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB lib/cmake/OpenVDB lib64/cmake/OpenVDB
                          share/cmake/OpenVDB)
  if(FIRN_OPENVDB_MODULE_DIR)
    list(APPEND CMAKE_MODULE_PATH ${FIRN_OPENVDB_MODULE_DIR})
  endif()
  find_package(OpenVDB REQUIRED MODULE)
endif()
