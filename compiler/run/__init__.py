"""Running compiled programs: the images in instruction-level simulators,
simavr for AVR (`compiler.run.simavr`) and gpsim for PIC16
(`compiler.run.gpsim`), the C on the host (`compiler.run.c`); recordings of
a run under a stimulus, scan by scan (`compiler.run.record`), which the
tests and benchmarks compare with the ladder simulator and `ladder test
--on` checks scenarios on."""
