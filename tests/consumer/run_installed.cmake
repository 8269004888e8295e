# The installed package, as consumers use it. dqkit is configured for one prefix and installed
# with `cmake --install --prefix` into another; a consumer builds with find_package; the tree is
# then moved, and consumers build again with pkg-config and with find_package from where it is now.
# The pkg-config consumer runs from the moved tree's bin/, where it finds the import worker in
# ../libexec/dqkit as an installed program would (the configured prefix does not exist).
file(REMOVE_RECURSE ${WORK_DIR})
set(configured ${WORK_DIR}/configured-prefix-never-created)
set(installed ${WORK_DIR}/installed)
set(moved ${WORK_DIR}/elsewhere/moved)
include(${CMAKE_CURRENT_LIST_DIR}/run.cmake)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/dqkit -DCMAKE_INSTALL_PREFIX=${configured} -DCMAKE_CXX_COMPILER=${CXX}
    -DDQKIT_BUILD_TESTS=OFF -DDQKIT_BUILD_BENCHMARKS=OFF -DDQKIT_BUILD_EXAMPLES=OFF -DDQKIT_BUILD_TOOLS=OFF
    -DDQKIT_BUILD_PYTHON=OFF -DDQKIT_BUILD_DEMOS=OFF)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/dqkit -j 2)
run(${CMAKE_COMMAND} --install ${WORK_DIR}/dqkit --prefix ${installed})
if(EXISTS ${configured})
  message(FATAL_ERROR "the install wrote to the configured prefix")
endif()

# find_package, from where it was installed.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer/project -B ${WORK_DIR}/consumer -DCMAKE_PREFIX_PATH=${installed}
    -DCMAKE_CXX_COMPILER=${CXX})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(${WORK_DIR}/consumer/consumer)

# The same consumer where the optional components' libraries are missing (Assimp, GLFW): it
# configures, builds and runs without them (their targets are not defined; dqkit::render needs
# GLFW only where dqkit was built with it); a consumer that requires one gets the package's reason.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer/project -B ${WORK_DIR}/consumer_without -DCMAKE_PREFIX_PATH=${installed}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_DISABLE_FIND_PACKAGE_assimp=ON -DCMAKE_DISABLE_FIND_PACKAGE_glfw3=ON)
if(output MATCHES "links dqkit::import" OR (WITH_GLFW AND output MATCHES "links dqkit::render"))
  message(FATAL_ERROR "without Assimp and GLFW, the consumer found components that need them:\n${output}")
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer_without)
run(${WORK_DIR}/consumer_without/consumer)
if(WITH_ASSIMP)
  file(WRITE ${WORK_DIR}/requires_import/CMakeLists.txt
    "cmake_minimum_required(VERSION 3.25)\nproject(requires_import LANGUAGES CXX)\nfind_package(dqkit REQUIRED CONFIG COMPONENTS io import)\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${WORK_DIR}/requires_import -B ${WORK_DIR}/requires_import/build
                  -DCMAKE_PREFIX_PATH=${installed} -DCMAKE_DISABLE_FIND_PACKAGE_assimp=ON
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(code EQUAL 0 OR NOT out MATCHES "dqkit::import needs Assimp")
    message(FATAL_ERROR "requiring dqkit::import without Assimp: expected the package's reason, got (${code}):\n${out}")
  endif()
endif()

# Moved: nothing may point to the old place.
file(MAKE_DIRECTORY ${WORK_DIR}/elsewhere)
file(RENAME ${installed} ${moved})
file(GLOB_RECURSE pc_files ${moved}/*.pc)
list(LENGTH pc_files pc_count)
if(pc_count LESS 3)
  message(FATAL_ERROR "expected a .pc file per component, found: ${pc_files}")
endif()
if(WITH_ASSIMP)
  set(component dqkit-import)
  set(consumer_flags -DDQKIT_CONSUMER_IMPORT)
  set(model ${MODELS}/glTF2/simple_skin/simple_skin.gltf)
else()
  set(component dqkit-io)
endif()
file(GLOB pc_dir LIST_DIRECTORIES true ${moved}/*/pkgconfig ${moved}/*/*/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
set(components ${component} dqkit-skin)
if(EXISTS ${pc_dir}/dqkit-render.pc)
  list(APPEND components dqkit-render)
  list(APPEND consumer_flags -DDQKIT_CONSUMER_RENDER)
  set(with_render ON)
endif()
run(pkg-config --cflags --libs ${components})
string(STRIP "${output}" flags)
if(flags MATCHES "${installed}|${configured}|/usr/local" OR NOT flags MATCHES "^-I${moved}/[^ ]*include -std=c\\+\\+20 (-I[^ ]* )*-L${moved}/")
  message(FATAL_ERROR "pkg-config flags do not follow the moved tree: ${flags}")
endif()
separate_arguments(flags)
file(MAKE_DIRECTORY ${moved}/bin)
run(${CXX} ${consumer_flags} ${SOURCE_DIR}/tests/consumer/project/main.cpp ${flags} -o ${moved}/bin/consumer_pc)
if(WITH_ASSIMP AND NOT EXISTS ${model})
  message(STATUS "no sample files at ${MODELS} (assimp-testmodels): the moved tree's import worker is not run")
  unset(model)
endif()
run(${moved}/bin/consumer_pc ${model})
if(with_render AND NOT output MATCHES "rendered")
  message(FATAL_ERROR "the moved tree's renderer did not run: ${output}")
endif()
if(model AND NOT output MATCHES "imported [0-9]+ joints")
  message(FATAL_ERROR "the moved tree's import did not run: ${output}")
endif()

# find_package, from the moved tree.
file(REMOVE_RECURSE ${WORK_DIR}/consumer)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer/project -B ${WORK_DIR}/consumer -DCMAKE_PREFIX_PATH=${moved}
    -DCMAKE_CXX_COMPILER=${CXX})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(${WORK_DIR}/consumer/consumer)
message(STATUS "installed with --prefix, moved: consumers build and run with find_package and pkg-config (${components})")
