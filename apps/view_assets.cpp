// lgi/apps/view_assets.cpp — the files of the page of `lgi view` (view.hpp), embedded in the executable: the
// viewer's template and code (apps/viewer/) and three.js r111 with its OrbitControls from Debian's libjs-three
// (their paths are compile definitions, apps/CMakeLists.txt). Each is a byte array [NAME, NAME_end).
#define LGI_EMBED(name, file)                                     \
  asm(".pushsection .rodata\n"                                    \
      ".global " #name "\n.global " #name "_end\n"               \
      #name ":\n.incbin \"" file "\"\n" #name "_end:\n.byte 0\n"  \
      ".popsection\n")

LGI_EMBED(lgi_viewer_html, LGI_VIEWER_HTML);
LGI_EMBED(lgi_viewer_js, LGI_VIEWER_JS);
#ifdef LGI_THREE_JS
LGI_EMBED(lgi_three_js, LGI_THREE_JS);
LGI_EMBED(lgi_orbit_js, LGI_ORBIT_JS);
#else  // built without libjs-three: empty, and viewer_available() is false
asm(".pushsection .rodata\n.global lgi_three_js\n.global lgi_three_js_end\n.global lgi_orbit_js\n.global lgi_orbit_js_end\n"
    "lgi_three_js:\nlgi_three_js_end:\nlgi_orbit_js:\nlgi_orbit_js_end:\n.byte 0\n.popsection\n");
#endif
