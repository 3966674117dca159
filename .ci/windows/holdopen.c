/* CI only: hold a file open (no FILE_SHARE_DELETE, as editors and virus scanners on Windows
 * do) until killed, so the smoke suite can run `gen` while another process holds a file of the
 * package folder. */
#include <windows.h>
#include <stdio.h>

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    HANDLE h = CreateFileA(argv[1], GENERIC_READ, FILE_SHARE_READ, NULL, OPEN_EXISTING,
                           FILE_ATTRIBUTE_NORMAL, NULL);
    if (h == INVALID_HANDLE_VALUE)
        return 1;
    printf("open\n");
    fflush(stdout);
    Sleep(INFINITE);
    return 0;
}
