/* libtbbmalloc.so.2 for the ThreadSanitizer stage (.ci/tsan_tbb): TBB's scalable allocator
 * calls forwarded to malloc and free, which TSan intercepts. Debian's tbbmalloc (loaded
 * through OpenCASCADE, a dependency of deal.II) hands out memory TSan cannot follow: TBB,
 * which takes its allocator when one is loaded, would reuse an arena's memory unseen and
 * TSan report its new use as a race with the old. */
#include <errno.h>
#include <malloc.h>
#include <stdlib.h>

void *scalable_malloc(size_t size) { return malloc(size); }
void scalable_free(void *p) { free(p); }
void *scalable_calloc(size_t n, size_t size) { return calloc(n, size); }
void *scalable_realloc(void *p, size_t size) { return realloc(p, size); }
size_t scalable_msize(void *p) { return p ? malloc_usable_size(p) : 0; }
int scalable_posix_memalign(void **p, size_t alignment, size_t size) { return posix_memalign(p, alignment, size); }
void *scalable_aligned_malloc(size_t size, size_t alignment)
{
  void *p = NULL;
  return posix_memalign(&p, alignment < sizeof(void *) ? sizeof(void *) : alignment, size) == 0 ? p : NULL;
}
void scalable_aligned_free(void *p) { free(p); }
void *scalable_aligned_realloc(void *p, size_t size, size_t alignment)
{
  void *q = scalable_aligned_malloc(size, alignment);
  if (q && p)
    {
      size_t old = malloc_usable_size(p);
      for (size_t i = 0; i < (old < size ? old : size); ++i)
        ((char *)q)[i] = ((const char *)p)[i];
      free(p);
    }
  return q;
}
int scalable_allocation_mode(int param, long value) { (void)param; (void)value; return 0; }
int scalable_allocation_command(int cmd, void *param) { (void)cmd; (void)param; return 0; }
