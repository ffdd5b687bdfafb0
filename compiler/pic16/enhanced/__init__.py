"""The enhanced mid-range PIC16 back end (PIC12F1840, PIC16F1512, 1516,
1527, 1824, 1827): the PIC16 family's parts whose device files say
`"core": "enhanced"`; the PIC16 back end hands them to `compile_enhanced`."""
