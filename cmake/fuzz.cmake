# libFuzzer targets (HYBRIDBENCH_FUZZ, clang only): fuzz_gltf (the glTF loader) and fuzz_config
# (the config parser), fed by tests/fuzz/corpus/<name>/ and run by scripts/fuzz.sh. They are built
# from the folders they need (base, scene, effects, config), not from the whole tool, with
# AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer's coverage. tinygltf is compiled in
# from its header so that the fuzzer sees its branches too.
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "HYBRIDBENCH_FUZZ needs clang for libFuzzer: configure with "
                      "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ (see scripts/fuzz.sh)")
endif()

# From src/plan/ the plan and registry, from src/effects/ each effect's schema (<name>/*_effect.cpp) and the list
# of built-in effects; their frame hooks are stand-ins (tests/fuzz/effect_hook_stubs.cpp).
file(GLOB_RECURSE FUZZ_CORE_SOURCES CONFIGURE_DEPENDS
     ${CMAKE_SOURCE_DIR}/src/base/*.cpp ${CMAKE_SOURCE_DIR}/src/scene/*.cpp ${CMAKE_SOURCE_DIR}/src/gltf/*.cpp
     ${CMAKE_SOURCE_DIR}/src/config/*.cpp)
file(GLOB FUZZ_EFFECT_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/plan/*.cpp
     ${CMAKE_SOURCE_DIR}/src/effects/*/*_effect.cpp ${CMAKE_SOURCE_DIR}/src/effects/builtin/*.cpp)
list(APPEND FUZZ_CORE_SOURCES ${FUZZ_EFFECT_SOURCES})
list(FILTER FUZZ_CORE_SOURCES EXCLUDE REGEX "_test\\.cpp$")
add_library(hybridfuzzcore STATIC ${FUZZ_CORE_SOURCES}
            ${CMAKE_SOURCE_DIR}/tests/fuzz/tinygltf_impl.cpp ${CMAKE_SOURCE_DIR}/tests/fuzz/effect_hook_stubs.cpp)
add_dependencies(hybridfuzzcore git_rev)
# The same include paths, definitions and warnings as hybridcore (and -Werror with it).
target_include_directories(hybridfuzzcore
                           PUBLIC $<TARGET_PROPERTY:hybridcore,INTERFACE_INCLUDE_DIRECTORIES>)
target_compile_definitions(hybridfuzzcore
                           PUBLIC $<TARGET_PROPERTY:hybridcore,INTERFACE_COMPILE_DEFINITIONS>)
target_compile_options(hybridfuzzcore PUBLIC $<TARGET_PROPERTY:hybridcore,INTERFACE_COMPILE_OPTIONS>
                       -fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all
                       -fno-omit-frame-pointer)
target_link_options(hybridfuzzcore PUBLIC -fsanitize=address,undefined)
target_link_libraries(hybridfuzzcore
                      PUBLIC nlohmann_json::nlohmann_json stb OpenSSL::Crypto Threads::Threads draco::draco
                             meshoptimizer::meshoptimizer PkgConfig::WEBP PkgConfig::AVIF ZLIB::ZLIB)

foreach(name gltf config)
  add_executable(fuzz_${name} ${CMAKE_SOURCE_DIR}/tests/fuzz/fuzz_${name}.cpp)
  target_link_libraries(fuzz_${name} PRIVATE hybridfuzzcore)
  target_link_options(fuzz_${name} PRIVATE -fsanitize=fuzzer)
endforeach()
