"""What each instruction does, written once: the lowering of a checked
program (`lower`) into the intermediate code (`ir`) that the simulator runs
as Python and the compiler's back ends translate for each part."""
