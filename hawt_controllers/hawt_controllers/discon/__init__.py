"""Bladed-style DISCON controller libraries (ROSCO) called through ctypes, and ROSCO's input files."""
