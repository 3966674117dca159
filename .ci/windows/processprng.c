/* A stand-in for bcryptprimitives.dll's ProcessPrng, which Rust's standard library imports on
 * Windows and Debian's Wine 8.0 does not provide. CI only: it lets the cross-built krlkit.exe
 * start under Wine (loaded from the executable's folder with WINEDLLOVERRIDES=bcryptprimitives=n,b).
 * Real Windows 10+ has ProcessPrng; this DLL never ships. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length); /* advapi32's RtlGenRandom */

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG n = length > 0x10000000 ? 0x10000000 : (ULONG)length;
        if (!SystemFunction036(data, n))
            return FALSE;
        data += n;
        length -= n;
    }
    return TRUE;
}
