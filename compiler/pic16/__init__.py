"""The PIC16 back end."""
