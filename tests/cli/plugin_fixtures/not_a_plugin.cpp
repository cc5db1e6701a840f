// A shared library without lgi_plugin_v1: `lgi --plugin` must refuse it as not an lgi plugin.
extern "C" int not_a_plugin_answer() { return 42; }
