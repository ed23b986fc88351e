/* Huge pages for the simulator's large arrays (bodies, grid cells, the
 * queue's events and buckets).  An event reads a few lines scattered over
 * tens of megabytes at 10^5 bodies; with 4 KB pages nearly each of them
 * also misses the TLB and walks the page tables (the more so in a virtual
 * machine), with 2 MB pages the whole working set stays mapped.  Linux maps
 * an anonymous range with transparent huge pages where it was advised to
 * (madvise MADV_HUGEPAGE; under the policy "madvise", this machine's, only
 * there); elsewhere this does nothing.  Only a hint: no result depends on
 * it. */
#define _DEFAULT_SOURCE         /* madvise under -std=c11 */
#include <stddef.h>
#include <stdint.h>

#include "m2c_sim_internal.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

void m2c_sim_huge_pages(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t huge = (uintptr_t)1 << 21;
    /* the whole 2 MB pages inside [p, p + bytes): madvise needs page-aligned
     * bounds, and a huge page never reaches outside the block */
    uintptr_t lo = ((uintptr_t)p + huge - 1) & ~(huge - 1);
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(huge - 1);
    if (p != NULL && hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);     /* refused: 4 KB pages */
#else
    (void)p;
    (void)bytes;
#endif
}
