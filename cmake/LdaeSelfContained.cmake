# A self-contained ldaec: the C++ runtime, ANTLR's runtime, fmt and KLU
# linked statically, so the dynamic loader maps libc and libm only. With
# them shared, resolving their symbols at every process start was a fifth
# of a whole Robertson run (docs/benchmarks.md, "Robertson"). Libraries and
# tests keep the shared ones; only a target with the property
# LDAE_SELF_CONTAINED (ldae_self_contained below) gets the static ones, as
# the libraries' link interfaces name both (ldae_static_alternative).
# Sanitizer builds keep everything shared.

if(LDAEC_SANITIZE OR LDAEC_LIBFUZZER)
  set(LDAE_CAN_SELF_CONTAIN OFF)
else()
  set(LDAE_CAN_SELF_CONTAIN ON)
endif()

# ldae_static_alternative(OUT LIB): LIB (a shared library's path), or the
# generator expression choosing its static archive beside it for targets
# that are self-contained. LIB unchanged when there is no archive.
function(ldae_static_alternative out lib)
  string(REGEX REPLACE "\\.so(\\.[0-9]+)*$" ".a" archive "${lib}")
  if(LDAE_CAN_SELF_CONTAIN AND NOT archive STREQUAL lib AND EXISTS "${archive}")
    set(${out} "$<IF:$<BOOL:$<TARGET_PROPERTY:LDAE_SELF_CONTAINED>>,${archive},${lib}>"
        PARENT_SCOPE)
  else()
    set(${out} "${lib}" PARENT_SCOPE)
  endif()
endfunction()

# ldae_static_alternatives(TARGET): the same for every shared library an
# imported INTERFACE target links (SUNDIALS::KLU: KLU and its orderings).
function(ldae_static_alternatives target)
  get_target_property(libs ${target} INTERFACE_LINK_LIBRARIES)
  if(NOT libs)
    return()
  endif()
  set(chosen)
  foreach(lib IN LISTS libs)
    ldae_static_alternative(alt "${lib}")
    list(APPEND chosen "${alt}")
  endforeach()
  set_property(TARGET ${target} PROPERTY INTERFACE_LINK_LIBRARIES "${chosen}")
endfunction()

# ldae_self_contained(TARGET): TARGET links the static alternatives and the
# C++ runtime statically. fmt has no archive: the target compiles fmt's
# own implementation header (compiler/driver/FmtLibrary.cpp), and
# --as-needed drops libfmt.so, which would bring libstdc++.so back.
# Not position-independent (-no-pie): as a PIE the dynamic loader applied
# 14,568 relative relocations (the vtables of ANTLR and LLVM-free C++) at
# every start, 1.2 M cycles, a tenth of a whole Robertson run.
function(ldae_self_contained target)
  if(NOT LDAE_CAN_SELF_CONTAIN)
    return()
  endif()
  set_property(TARGET ${target} PROPERTY LDAE_SELF_CONTAINED ON)
  set_property(TARGET ${target} PROPERTY POSITION_INDEPENDENT_CODE OFF)
  target_compile_options(${target} PRIVATE -fno-pie)
  target_link_options(${target} PRIVATE -static-libstdc++ -static-libgcc
                      -Wl,--as-needed -no-pie)
endfunction()
