# ctest labels of the discovered gtest tests, by test name (run by ctest after the discovered
# tests are defined: tests/CMakeLists.txt adds this file to TEST_INCLUDE_FILES after them).
#
# Every test has exactly one kind:
#   judge        an independent reader or decoder checks our output (Mesa llvmpipe, ktx-parse,
#                Chromium, three.js, Godot 4.6, OpenImageIO's DDS reader, the bakers' own runtime formulas)
#   integration  runs the ahdpack binary or another process, or reads the real bakes (tests/data)
#   accuracy     an error bound measured on many inputs (the figures docs/accuracy.md quotes)
#   unit         everything else: in process, one stage, seconds for the whole label
# and may add:
#   slow         took 20 s or more in the fresh-clone run of 2026-12-02 (2 cores at load ≈ 15) (ctest -LE slow leaves them out)
#   nosan        left out of the ASan/UBSan run (scripts/sanitize.sh): a browser, the installed
#                package built with the default compiler, the three.js render, three accuracy sweeps the instrumented
#                suite already covers on fewer inputs, the hundred concurrent conversions (a race
#                test: ASan finds no races, and instrumented it takes minutes); the command-line runs of
#                converters whose code the instrumented unit tests already run in process (Cli,
#                BakerBevy, Preview, Preview3d, Plot, Verify, Atlas, MeshRaster's and ColourSpace's
#                CLI cases: 190 s of the 800 s the instrumented suite took, 2026-12-04); the runs on
#                files we did not write (BadInput*, Cook, OutputFaults, OutputSet, Godot*) stay
# A new test lands in `unit` unless a pattern below names it.
# The script tests (add_test in tests/CMakeLists.txt: Consumer.*, Python.*, Docs.*) are labelled
# there, beside their add_test: ctest includes this file before it defines them.

set(_judge "^(Bc6hJudge|PackedFloatMesa|RgtcMesa|Profiles/ShaderRender|KtxParse|PreviewChromium|ThreeRender|ThreeScene|GodotAddon|GodotAddonScene|DecodeVsRuntime)\\.|^Container\\.OpenImageIOReadsOurDds$")
set(_integration "^(Cli|KeyedReadsCli|CacheDirectLookupCli|Golden|BakerUnity|BakerBevy|BakerPlain|Verify|Plot|Preview|Preview3d|BenchConvert|Consumer|OutputSet)\\.|^ColourSpace\\.(Numpy|Cli)|^Atlas\\.(RealGodot42|FourPageGodotAtlas|UnknownPageCount)|^BadInput\\.Cli|^Placement\\.ConvertWith|^MeshRaster\\.(BadMeshes|ConvertWithMesh|MeshAxes)|^DirectionPlanes\\.(PlainLightmapWritesOnlyIz|KeepAndDrop)|^Layout\\.GodotPackedMatchesSource|^(OutputFaults|Cook|GodotScene|IzScale|Projects/GodotCorpus|GodotCorpusWrongBake|GodotCorpusArrays)\\.|^GodotFbx\\.DroppedEntry|^BadInputRound2\\.(CatalogueUnderThreeGib|BadMaxSizeEnvironment|InputReplacedWhileRead)|^BadInputRound3\\.|^BadInputRound3Readers\\.HostileInputs")
set(_accuracy "^Truth\\.|^FitWindow\\.NoisyScene|^Bc6h\\.(SharedImagesBeatTheFastestPublicEncoder|MaxOnCropsOfTheSharedImages|FastBeatsTheRealTimePeerOnTheSharedImages)$|^Fit\\.(ClosedFormTMatchesBruteForceSearch|MillionRandomTexels)|^FitRefine\\.(ErrorRatiosAgainstUnconstrainedLeastSquares|IssueMeasureSampledDirections|NeverWorseThanTheLinearDirectionPerTexel|MillionRandomTexels|FilteredErrorOnTheAnalyticScene|PairGuardBounds|CoherencePass)|^ErrorEstimate\\.(AgreesWithFullMeasurement|ConversionEstimateAgrees)|^Bc4\\.EncoderIsCloseToExhaustiveSearch$")
set(_slow "^(Consumer|BenchConvert|Truth|GodotAddon|GodotAddonScene)\\.|^Atlas\\.FourPageGodotAtlas|^Cli\\.(BatchOfSmallFiles|EveryProfileAndContainer)|^Bc6h\\.MaxOnCrops|^OutputSet\\.KilledBeforeEachRename|^OutputFaults\\.(HundredPairs|SignalBetweenRenames|KilledAtEveryRename)|^Cook\\.KeyCoversEveryInput|^(Verify|Preview)\\.GodotProject")
set(_nosan "^(Consumer|PreviewChromium|ThreeRender|ThreeScene|GodotAddon|GodotAddonScene|Truth|Cli|BakerBevy|Preview3d|Plot|Preview|Verify|Atlas)\\.|^MeshRaster\\.(BadMeshes|ConvertWithMesh|MeshAxes)|^ColourSpace\\.(Numpy|Cli)|^OutputFaults\\.HundredPairsOfConcurrentConversions|^Bc6h\\.(MaxOnCropsOfTheSharedImages|SharedImagesBeatTheFastestPublicEncoder)$|^Fit\\.ClosedFormTMatchesBruteForceSearch$")

# Every test of the Mesa judges' binary (tests/gl) is a judge by its folder, whatever its name.
set(_gl_tests "${ahd_gl_tests_TESTS}")
foreach(_t IN LISTS ahd_tests_TESTS ahd_gl_tests_TESTS)
  list(FIND _gl_tests "${_t}" _in_gl)
  if(_t MATCHES "${_judge}" OR NOT _in_gl EQUAL -1)
    set(_labels judge)
  elseif(_t MATCHES "${_integration}")
    set(_labels integration)
  elseif(_t MATCHES "${_accuracy}")
    set(_labels accuracy)
  else()
    set(_labels unit)
  endif()
  if(_t MATCHES "${_slow}")
    list(APPEND _labels slow)
  endif()
  if(_t MATCHES "${_nosan}")
    list(APPEND _labels nosan)
  endif()
  set_tests_properties("${_t}" PROPERTIES LABELS "${_labels}")
endforeach()
