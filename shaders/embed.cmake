# Writes OUT: a header with every shader as a raw string literal (run at build time).
file(READ ${SRC}/crowd.vert VERT)
file(READ ${SRC}/crowd.frag FRAG)
file(WRITE ${OUT}.tmp "// Generated from shaders/ by shaders/embed.cmake: do not edit.\n#pragma once\n")
file(APPEND ${OUT}.tmp "inline constexpr const char* kCrowdVert = R\"glsl(${VERT})glsl\";\n")
file(APPEND ${OUT}.tmp "inline constexpr const char* kCrowdFrag = R\"glsl(${FRAG})glsl\";\n")
file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
