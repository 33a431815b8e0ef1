// A mesh file that would write a file through Printf's redirection.
Include "panel.geo";
Printf("PRINTF-WROTE-THIS") > "printf_marker.txt";
