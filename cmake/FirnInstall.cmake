# `cmake --install BUILD --prefix P` installs Firn as a library other CMake projects use through
#   find_package(Firn REQUIRED)
#   target_link_libraries(app PRIVATE Firn::engine)
# (examples/embed), and the `firn` command line:
#
#   P/bin/firn
#   P/lib/libfirn_engine.a, libfirn_voxelizer.a           (static; Firn::engine links Firn::voxelizer)
#   P/include/firn/{Error.h, gl/, gpu/, io/, render/, run/, scene/, sim/, surface/}   engine/**/*.h
#   P/include/firn/<dir>/*.h                               shaders/**/*.h (headers shared by C++ and GLSL)
#   P/include/firn/voxelizer/*.h                           voxelizer/*.h
#   P/lib/cmake/Firn/FirnConfig.cmake, FirnConfigVersion.cmake, FirnFindOpenVDB.cmake, FirnTargets*.cmake
#
# include/firn is Firn::engine's include dir, so the engine's own includes ("gl/Buffer.h", "Error.h",
# "common/gpu_contract.h", "voxelizer/Voxelizer.h") resolve as they do in the source tree. Shaders and the
# built-in scene are compiled into libfirn_engine.a: nothing else is needed at run time.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(FIRN_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Firn)

# Consumers compile the engine's headers as C++17 (std::filesystem, std::optional) whatever their own default.
target_compile_features(firn_engine PUBLIC cxx_std_17)
target_compile_features(firn_voxelizer PUBLIC cxx_std_17)
set_target_properties(firn_engine PROPERTIES EXPORT_NAME engine)

# Every header under ROOT (found again at each build, like the embedded shaders), into include/firn/SUBDIR
# keeping its path relative to ROOT. A loop of install(FILES) rather than install(DIRECTORY … FILES_MATCHING):
# the latter also creates the folders holding no header (shaders/sim, shaders/render).
function(firn_install_headers root subdir)
  file(GLOB_RECURSE headers RELATIVE ${root} CONFIGURE_DEPENDS ${root}/*.h)
  foreach(header ${headers})
    get_filename_component(dir ${subdir}/${header} DIRECTORY)
    string(REGEX REPLACE "^/+" "" dir "${dir}")
    install(FILES ${root}/${header} DESTINATION include/firn/${dir} COMPONENT Development)
  endforeach()
endfunction()
firn_install_headers(${PROJECT_SOURCE_DIR}/engine "")
firn_install_headers(${PROJECT_SOURCE_DIR}/shaders "")
firn_install_headers(${PROJECT_SOURCE_DIR}/voxelizer voxelizer)

install(TARGETS firn_engine firn_voxelizer EXPORT FirnTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Development)
install(TARGETS firn RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT Runtime)

install(EXPORT FirnTargets NAMESPACE Firn:: DESTINATION ${FIRN_INSTALL_CMAKEDIR} COMPONENT Development)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/FirnConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/FirnConfig.cmake
                              INSTALL_DESTINATION ${FIRN_INSTALL_CMAKEDIR})
# 0.x: a new minor version may change the API.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/FirnConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/FirnConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/FirnConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/FirnFindOpenVDB.cmake
        DESTINATION ${FIRN_INSTALL_CMAKEDIR} COMPONENT Development)
