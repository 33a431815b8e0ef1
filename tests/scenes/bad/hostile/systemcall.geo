// A mesh file that would run a shell command when a scene using it is merely checked.
SystemCall "echo SYSTEMCALL-RAN > syscall_marker.txt";
Include "panel.geo";
