/* Test-only stand-in for Windows' bcryptprimitives.dll, for Wine 8, which lacks it.
 *
 * Rust's standard library (1.78 and later) imports ProcessPrng from bcryptprimitives.dll, which
 * every Windows 10 and later has; Wine 8 does not, so no Rust DLL loads there. This forwards to
 * BCryptGenRandom, which Wine has. tests/cross/setup.sh builds it with mingw-w64 into the test
 * Wine prefix only: it is never shipped in an FMU. */
#include <windows.h>
#include <bcrypt.h>

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len)
{
    while (len > 0) {
        ULONG n = len > 0x7fffffff ? 0x7fffffff : (ULONG)len;
        if (BCryptGenRandom(NULL, data, n, BCRYPT_USE_SYSTEM_PREFERRED_RNG) != 0)
            return FALSE;
        data += n;
        len -= n;
    }
    return TRUE;
}
