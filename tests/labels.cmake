# ctest labels of the discovered gtest tests (run by ctest after the discovered tests are defined:
# tests/CMakeLists.txt adds this file to TEST_INCLUDE_FILES after them).
#
# Every test has exactly one kind, its binary's, that is its folder's (tests/CMakeLists.txt):
#   unit         tests/unit: in process, one stage, seconds for the whole label
#   integration  tests/integration: runs the ahdpack binary or another process, or reads the real bakes
#   judge        tests/judges: an independent reader or decoder checks our output (Mesa llvmpipe,
#                ktx-parse, Chromium, three.js, Godot 4.6, the bakers' own runtime formulas)
#   accuracy     tests/accuracy: an error bound measured on many inputs (the figures docs/accuracy.md quotes)
# except the tests named below (a file of one kind holding a test of another: keep it short); a new
# test goes in a file of its kind's folder. Helpers that tests of two kinds share live in
# tests/support (e.g. fit_refine_fixture.h for tests/unit and tests/accuracy fit_refine_test.cpp).
# A test may add:
#   slow         took 20 s or more in the fresh-clone run of 2026-12-02 (2 cores at load ≈ 15) (ctest -LE slow leaves them out)
#   nosan        left out of the ASan/UBSan run (scripts/sanitize.sh): a browser, the installed
#                package built with the default compiler, the three.js render, three accuracy sweeps the instrumented
#                suite already covers on fewer inputs, the hundred concurrent conversions (a race
#                test: ASan finds no races, and instrumented it takes minutes); the command-line runs of
#                converters whose code the instrumented unit tests already run in process (Cli,
#                BakerBevy, Preview, Preview3d, Plot, Verify, Atlas, MeshRaster's and ColourSpace's
#                CLI cases: 190 s of the 800 s the instrumented suite took, 2026-12-04); the runs on
#                files we did not write (BadInput*, Cook, OutputFaults, OutputSet, Godot*) stay; the
#                strace comparison of files read and keyed (KeyedReadsCli: strace around CLI runs); `report
#                truth` on the path-traced scenes (ReportTruth*: lab code whose formats TruthFormats runs);
#                the low-resolution profiles through the CLI (LowResProfiles: 28 s instrumented, their fit and
#                planes run in process in LowResPlanes)
# The script tests (add_test in tests/CMakeLists.txt: Consumer.*, Python.*, Docs.*, Layering.*) are
# labelled there, beside their add_test: ctest includes this file before it defines them.

# Tests of another kind than their file's folder ("^$": none).
set(_as_unit "^BakerRecipes\\.ReadmeHoldsTheTestedCommands$")  # the README check beside the recipes it checks
set(_as_integration "^$")
set(_as_judge "^$")
set(_as_accuracy "^$")
set(_slow "^(Consumer|BenchConvert|Truth|GodotAddon|GodotAddonScene)\\.|^Atlas\\.FourPageGodotAtlas|^Cli\\.(BatchOfSmallFiles|EveryProfileAndContainer)|^Bc6h\\.MaxOnCrops|^OutputSet\\.KilledBeforeEachRename|^OutputFaults\\.(HundredPairs|SignalBetweenRenames|KilledAtEveryRename)|^Cook\\.KeyCoversEveryInput|^(Verify|Preview|Preview3d)\\.GodotProject")
set(_nosan "^(KeyedReadsCli|Consumer|PreviewChromium|ThreeRender|ThreeScene|GodotAddon|GodotAddonScene|Truth|ReportTruthAnchors|ReportTruthBudgets|LowResProfiles|Cli|BakerBevy|Preview3d|Plot|Preview|Verify|Atlas)\\.|^MeshRaster\\.(BadMeshes|ConvertWithMesh|MeshAxes)|^ColourSpace\\.(Numpy|Cli)|^OutputFaults\\.HundredPairsOfConcurrentConversions|^Bc6h\\.(MaxOnCropsOfTheSharedImages|SharedImagesBeatTheFastestPublicEncoder)$|^Fit\\.ClosedFormTMatchesBruteForceSearch$")

foreach(_kind unit integration judge accuracy)
  foreach(_t IN LISTS ahd_${_kind}_tests_TESTS)
    set(_labels ${_kind})
    if(_t MATCHES "${_as_unit}")
      set(_labels unit)
    elseif(_t MATCHES "${_as_integration}")
      set(_labels integration)
    elseif(_t MATCHES "${_as_judge}")
      set(_labels judge)
    elseif(_t MATCHES "${_as_accuracy}")
      set(_labels accuracy)
    endif()
    if(_t MATCHES "${_slow}")
      list(APPEND _labels slow)
    endif()
    if(_t MATCHES "${_nosan}")
      list(APPEND _labels nosan)
    endif()
    set_tests_properties("${_t}" PROPERTIES LABELS "${_labels}")
  endforeach()
endforeach()
