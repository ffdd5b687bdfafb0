"""The text form: LDmicro's Export as Text drawing, read and written."""
