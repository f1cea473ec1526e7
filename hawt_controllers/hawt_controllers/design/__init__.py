"""Controller design from the plant: baseline and IPC tuning, linear models, their validation, tunings."""
