# Finds every third-party dependency once, with a message that names the Debian
# package and the script that installs it when something is missing.
set(SULCUS_INSTALL_HINT "run scripts/install-deps.sh (as root) to install everything Sulcus needs")

macro(sulcus_find name debian_package)
  find_package(${name} ${ARGN} QUIET)
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR
      "Sulcus: ${name} not found (Debian package: ${debian_package}); ${SULCUS_INSTALL_HINT}.")
  endif()
endmacro()

sulcus_find(Eigen3 libeigen3-dev CONFIG)
# CONFIG is required: without it CGAL's own FindOpenMesh module is used and fails.
sulcus_find(OpenMesh libopenmesh-dev CONFIG)
sulcus_find(CLI11 libcli11-dev CONFIG)
sulcus_find(Threads libc6-dev)
sulcus_find(CGAL libcgal-dev CONFIG)
sulcus_find(yaml-cpp libyaml-cpp-dev CONFIG)
sulcus_find(PkgConfig pkg-config)
sulcus_find(SQLite3 libsqlite3-dev)
# A pkg-config module as the imported target PkgConfig::<prefix>.
macro(sulcus_pkg prefix module debian_package)
  pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
  if(NOT ${prefix}_FOUND)
    message(FATAL_ERROR
      "Sulcus: ${module} not found (Debian package: ${debian_package}); "
      "${SULCUS_INSTALL_HINT}.")
  endif()
endmacro()
sulcus_pkg(sodium libsodium libsodium-dev)
sulcus_pkg(zstd libzstd libzstd-dev)
sulcus_pkg(libpq libpq libpq-dev)
sulcus_pkg(libcurl libcurl libcurl4-openssl-dev)
sulcus_pkg(libusb libusb-1.0 libusb-1.0-0-dev)
sulcus_pkg(icu_uc icu-uc libicu-dev)
sulcus_pkg(icu_i18n icu-i18n libicu-dev)

if(SULCUS_BUILD_TESTS)
  sulcus_find(GTest "libgtest-dev libgmock-dev" CONFIG)
endif()
if(SULCUS_BUILD_BENCHMARKS)
  sulcus_find(benchmark libbenchmark-dev CONFIG)
endif()

if(SULCUS_BUILD_UI)
  # VTK 9.1 on Debian 12 references VTK::mpi; MPI's C component must exist first.
  sulcus_find(MPI "libopenmpi-dev (pulled in by libvtk9-dev)" COMPONENTS C)
  sulcus_find(Qt5 qtbase5-dev COMPONENTS Widgets OpenGL)
  sulcus_find(VTK "libvtk9-dev libvtk9-qt-dev" COMPONENTS
    CommonCore CommonDataModel RenderingCore RenderingOpenGL2 InteractionStyle
    RenderingFreeType IOImage FiltersSources GUISupportQt ChartsCore ViewsContext2D
    RenderingContextOpenGL2)
endif()
