// Make/Ninja depfiles: what `convert --depfile` writes so a build system knows every file a
// conversion read (files/input_record.h) and rebuilds it when any of them changes.
#pragma once
#include <ahd/cook.h>

// depfile_text and write_depfile are declared in the public <ahd/cook.h>.
