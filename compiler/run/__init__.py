"""Running compiled images in instruction-level simulators: simavr for AVR
(`compiler.run.simavr`), gpsim for PIC16 (`compiler.run.gpsim`). The tests
and benchmarks compare them with the ladder simulator."""
