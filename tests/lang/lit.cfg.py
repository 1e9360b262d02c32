# lit configuration of the language suite: every .lsd file under tests/lang
# is a test with `// RUN:` lines, checked with FileCheck.
import os
import lit.formats

config.name = "ldaec-lang"
config.test_format = lit.formats.ShTest(execute_external=False)
config.suffixes = [".lsd"]
config.excludes = ["Inputs"]
config.test_source_root = os.path.dirname(__file__)
config.test_exec_root = os.path.join(config.ldaec_obj_root, "tests", "lang")

config.environment["PATH"] = os.pathsep.join(
    [config.ldaec_bin_dir, config.ldaec_tools_dir, config.environment.get("PATH", "")])
# Compiled models are cached in the build tree, never in the user's cache
# directory (docs/codegen.md, "The object cache").
config.environment["LDAEC_CACHE_DIR"] = os.path.join(
    config.ldaec_obj_root, "tests", "cache")
if getattr(config, "ldaec_sanitize", False):
    config.available_features.add("asan")

config.substitutions.append(("%ldaec", os.path.join(config.ldaec_bin_dir, "ldaec")))
config.substitutions.append(("%stdlib", os.path.join(config.ldaec_src_root, "stdlib")))
config.substitutions.append(("%examples", os.path.join(config.ldaec_src_root, "examples")))
# The Modelica Standard Library as a user's installation (test data beside
# the checkout, ../shared/msl): tests that load it say REQUIRES: msl.
msl = os.path.normpath(os.path.join(config.ldaec_src_root, "..", "shared", "msl"))
if os.path.isdir(os.path.join(msl, "Modelica")):
    config.available_features.add("msl")
config.substitutions.append(("%msl", msl))
# MODELICAPATH is the test's to set, never the caller's.
config.environment.pop("MODELICAPATH", None)
