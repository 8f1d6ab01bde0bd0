"""The parts the commands are made of: each study's model, table and chart helpers (the flexible
bat's beam and engines, the friction and sweep charts, the sweep's options, the throughput
benchmark). None runs as a command; the commands are the modules of ``experiments`` itself."""
